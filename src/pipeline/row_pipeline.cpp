#include "pipeline/row_pipeline.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "fss/pipeline/metrics.h"

namespace fss {

void ImageRowSink::consume_row(int channel, int row, std::span<const double> values) {
  std::copy(values.begin(), values.end(), image_.row(channel, row));
}

ObservationParams observation_params(const SimulationOptions& options, const Geometry& geometry) {
  ObservationParams params;
  params.velocity = options.velocity_px_per_slot;
  params.dt = options.dt;
  params.snr = options.snr;
  params.aggregate_noise = options.noise == NoiseModel::kAggregated;
  params.sensor = options.sensor;
  // the readouts that reach the restoration: the observed crop [h, h + Wa)
  params.clipping_first_column = geometry.half_blur;
  params.clipping_end_column = geometry.half_blur + geometry.observed_width;
  return params;
}

RowPipeline::RowPipeline(const Image& input, const ShutterCode& code,
                         const SimulationOptions& options, const Geometry& geometry,
                         double observed_divisor)
    : RowPipeline(
          input,
          RowObserver(input.width, code.gains, options.mode, observation_params(options, geometry)),
          RowRestorer(geometry, code.gains,
                      options.restore_velocity_px_per_slot.value_or(options.velocity_px_per_slot),
                      options.dt),
          options, geometry, observed_divisor) {}

RowPipeline::RowPipeline(const Image& input, const RowObserver& observer,
                         const RowRestorer& restorer, const SimulationOptions& options,
                         const Geometry& geometry, double observed_divisor)
    : input_(input),
      geometry_(geometry),
      threads_(options.threads),
      observed_divisor_(observed_divisor),
      observer_(observer.with_noise(observation_params(options, geometry))),
      restorer_(restorer) {
  const auto samples = static_cast<std::size_t>(input.width) * input.height * input.channels;
  if (records_plans(observer_.aggregates_noise(), options.trials, samples)) {
    plans_.resize(static_cast<std::size_t>(input.channels) * input.height);
  }
}

std::size_t RowPipeline::plan_bytes(int width, int height, int channels,
                                    const SimulationOptions& options, int code_length, int groups) {
  const auto w = static_cast<std::size_t>(width);
  const auto rows = static_cast<std::size_t>(height) * static_cast<std::size_t>(channels);
  const bool aggregated =
      options.noise == NoiseModel::kAggregated && options.mode == ShutterMode::kNumerical;
  if (!records_plans(aggregated, options.trials, w * rows)) return 0;
  // A frame's record, its two arrays' allocations, and the frames vector's
  // doubling: 192 bytes; the plan itself and M and V's allocations: 256.
  constexpr std::size_t kFrameBytes = 192;
  constexpr std::size_t kRowBytes = sizeof(AggregatedRowPlan) + 256;
  const std::size_t frames = std::min(w, static_cast<std::size_t>(std::max(code_length, 0)));
  const std::size_t group_bytes =
      (8 * w + kFrameBytes) * static_cast<std::size_t>(std::max(groups, 0));
  return rows * (kRowBytes + 28 * w + kFrameBytes * frames + group_bytes);
}

// The buffers of one thread and the three steps of a row.
class RowPipeline::Worker {
 public:
  explicit Worker(const RowPipeline& pipeline)
      : pipeline_(pipeline),
        observer_scratch_(pipeline.observer_),
        restorer_scratch_(pipeline.restorer_),
        observation_(static_cast<std::size_t>(pipeline.geometry_.width)),
        row_(static_cast<std::size_t>(pipeline.geometry_.output_width)) {}

  // observation = o (noisy) or E[o] (no seed) of input row (c, y); with a
  // plan (aggregated noise), replayed when recorded, else recorded.
  // The clipped readouts of a noise-free observation (none for a noisy one).
  ReadoutClipping observe(int c, int y, std::optional<std::uint64_t> noise_seed,
                          AggregatedRowPlan* plan = nullptr) {
    const RowObserver& observer = pipeline_.observer_;
    if (plan != nullptr && plan->recorded) {
      observer.replay(*plan, *noise_seed, c, y, observer_scratch_, observation_);
      return {};
    }
    if (plan != nullptr) observer.record_plan(plan, observer_scratch_);
    pipeline_.observer_.load_row(pipeline_.input_.row(c, y), observer_scratch_);
    return pipeline_.observer_.observe(noise_seed.has_value(), noise_seed.value_or(0), c, y,
                                       observer_scratch_, observation_);
  }

  // observation = o with the noise of `seed` and expectation = E[o] of input
  // row (c, y), one load and one set of exposures for both (the plan of
  // aggregated noise recorded when given); returns Var(o), W values, and
  // adds the row's clipped readouts to `clipping`.
  const double* observe_first(int c, int y, std::uint64_t seed, AggregatedRowPlan* plan,
                              ReadoutClipping& clipping) {
    const RowObserver& observer = pipeline_.observer_;
    expectation_.resize(observation_.size());
    variance_.resize(observation_.size());
    if (plan != nullptr) observer.record_plan(plan, observer_scratch_);
    observer.load_row(pipeline_.input_.row(c, y), observer_scratch_);
    clipping += observer.observe(seed, c, y, observer_scratch_,
                                 RowObserver::Outputs{observation_, expectation_, variance_});
    return variance_.data();
  }

  // expectation = E[o] of input row (c, y) and, when `variances`, Var(o) (returned; null
  // otherwise), adding the row's clipped readouts to `clipping`: observe_first() without the
  // noisy observation, the same bits.
  const double* observe_expectation(int c, int y, bool variances, ReadoutClipping& clipping) {
    const RowObserver& observer = pipeline_.observer_;
    expectation_.resize(observation_.size());
    variance_.resize(variances ? observation_.size() : 0);
    observer.load_row(pipeline_.input_.row(c, y), observer_scratch_);
    clipping += observer.observe(0, c, y, observer_scratch_,
                                 RowObserver::Outputs{{}, expectation_, variance_});
    return variances ? variance_.data() : nullptr;
  }

  // Sends observation columns [3h, 3h + Wo) / divisor to `sink`; false when
  // one is not finite.
  bool send_observed(int c, int y, ObservedRowSink& sink) {
    const double* observed = observation_.data() + 3 * pipeline_.geometry_.half_blur;
    bool finite = true;
    for (std::size_t x = 0; x < row_.size(); ++x) {
      row_[x] = observed[x] / pipeline_.observed_divisor_;
      finite = finite && std::isfinite(row_[x]);
    }
    sink.consume_row(c, y, row_);
    return finite;
  }

  // restored[0 .. Wo) from the observation, into `restored`.
  void restore(double* restored) {
    pipeline_.restorer_.restore(observation_.data(), restorer_scratch_, restored);
  }

  // The restoration of the expectation observe_first() made, into the
  // worker's row.
  const double* restore_expectation() {
    pipeline_.restorer_.restore(expectation_.data(), restorer_scratch_, row_.data());
    return row_.data();
  }

 private:
  const RowPipeline& pipeline_;
  RowObserver::Scratch observer_scratch_;
  RowRestorer::Scratch restorer_scratch_;
  std::vector<double> observation_;  // W values
  std::vector<double> expectation_;  // W values, E[o] (first trial)
  std::vector<double> variance_;     // W values, Var(o) (first trial)
  std::vector<double> row_;          // Wo values: an observed or restored row
};

template <typename PerItem>
void RowPipeline::for_each_item(int count, const PerItem& per_item) const {
  if (count <= 0) return;
  const int workers = std::min(resolve_thread_count(threads_), count);
  std::atomic<int> next{0};
  parallel_for(workers, workers, [&](int, int) {
    Worker worker(*this);
    for (int i = next++; i < count; i = next++) per_item(worker, i);
  });
}

bool RowPipeline::restore_all(std::optional<std::uint64_t> noise_seed, Image& restored,
                              ObservedRowSink* observed, ReadoutClipping* clipping) const {
  std::atomic<bool> observed_finite{true};
  std::atomic<std::uint64_t> saturated{0};
  std::atomic<std::uint64_t> near_zero{0};
  const int height = input_.height;
  for_each_item(input_.channels * height, [&](Worker& worker, int r) {
    const int c = r / height;
    const int y = r % height;
    const bool planned = noise_seed.has_value() && !plans_.empty();
    const ReadoutClipping row_clipping =
        worker.observe(c, y, noise_seed, planned ? &plans_[static_cast<std::size_t>(r)] : nullptr);
    saturated += row_clipping.saturated;  // integer sums: any order gives the same total
    near_zero += row_clipping.near_zero;
    if (observed != nullptr && !worker.send_observed(c, y, *observed)) observed_finite = false;
    worker.restore(restored.row(c, y));
  });
  if (clipping != nullptr) *clipping = {saturated.load(), near_zero.load()};
  return observed_finite;
}

template <typename PerRow>
NoiseFreeRun RowPipeline::noise_free_blocks(int first, int end, bool variances,
                                            const PerRow& per_row) const {
  const int rows = input_.channels * input_.height;
  const int wa = geometry_.observed_width;
  // Blocks of rows fixed by the image alone, at most kVarianceBlocks of them.
  constexpr int kVarianceBlocks = 64;
  const int blocks = std::min(rows, kVarianceBlocks);
  std::vector<double> row_errors(static_cast<std::size_t>(rows));
  std::vector<double> block_sums(variances ? static_cast<std::size_t>(blocks) * wa : 0, 0.0);
  std::vector<ReadoutClipping> block_clipping(static_cast<std::size_t>(blocks));
  for_each_item(blocks, [&](Worker& worker, int b) {
    double* sums = variances ? block_sums.data() + static_cast<std::ptrdiff_t>(b) * wa : nullptr;
    const auto row_begin = static_cast<int>(static_cast<long long>(rows) * b / blocks);
    const auto row_end = static_cast<int>(static_cast<long long>(rows) * (b + 1) / blocks);
    for (int r = row_begin; r < row_end; ++r) {
      row_errors[r] = per_row(worker, r, sums, block_clipping[static_cast<std::size_t>(b)]);
    }
  });
  NoiseFreeRun run;
  ReadoutClipping clipping;
  for (const ReadoutClipping& block : block_clipping) clipping += block;
  run.saturated_readouts = clipping.saturated;
  run.near_zero_readouts = clipping.near_zero;
  double total = 0.0;
  for (const double e : row_errors) total += e;
  // sqrt(mean (truth - restored)^2), as rmse() divides
  run.rmse =
      std::sqrt(total / (static_cast<double>(end - first) * input_.height * input_.channels));
  if (!variances) return run;
  // S(j) = sum over the blocks, in order
  run.crop_variance_sums.assign(static_cast<std::size_t>(wa), 0.0);
  for (int b = 0; b < blocks; ++b) {
    const double* sums = block_sums.data() + static_cast<std::ptrdiff_t>(b) * wa;
    for (int j = 0; j < wa; ++j) run.crop_variance_sums[j] += sums[j];
  }
  return run;
}

RowPipeline::FirstTrial RowPipeline::first_trial(std::uint64_t noise_seed, int first, int end,
                                                 Image& restored, ObservedRowSink* observed) const {
  const int wa = geometry_.observed_width;
  const int h = geometry_.half_blur;
  std::atomic<bool> observed_finite{true};
  FirstTrial trial;
  trial.noise_free = noise_free_blocks(
      first, end, true, [&](Worker& worker, int r, double* sums, ReadoutClipping& clipping) {
        const int c = r / input_.height;
        const int y = r % input_.height;
        AggregatedRowPlan* plan = plans_.empty() ? nullptr : &plans_[static_cast<std::size_t>(r)];
        const double* variance =
            worker.observe_first(c, y, noise_seed, plan, clipping) + h;  // crop column 0
        if (sums != nullptr) {  // first_trial always asks for the variances
          for (int j = 0; j < wa; ++j) sums[j] += variance[j];
        }
        if (observed != nullptr && !worker.send_observed(c, y, *observed)) observed_finite = false;
        worker.restore(restored.row(c, y));
        return row_squared_error(input_.row(c, y) + 3 * h, worker.restore_expectation(), first,
                                 end);
      });
  trial.observed_finite = observed_finite.load();
  return trial;
}

NoiseFreeRun RowPipeline::noise_free_pass(int first, int end, bool variances) const {
  const int wa = geometry_.observed_width;
  const int h = geometry_.half_blur;
  return noise_free_blocks(
      first, end, variances, [&](Worker& worker, int r, double* sums, ReadoutClipping& clipping) {
        const int c = r / input_.height;
        const int y = r % input_.height;
        const double* variance = worker.observe_expectation(c, y, variances, clipping);
        if (variance != nullptr && sums != nullptr) {
          for (int j = 0; j < wa; ++j) sums[j] += variance[h + j];  // crop column j
        }
        return row_squared_error(input_.row(c, y) + 3 * h, worker.restore_expectation(), first,
                                 end);
      });
}

}  // namespace fss
