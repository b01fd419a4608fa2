#include "pipeline/row_pipeline.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "fss/core/parallel.h"
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
          input, RowObserver(input.width, code.gains, options.mode,
                                 observation_params(options, geometry)),
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
  if (observer_.aggregates_noise() && options.trials > 1 && samples <= kMaxPlannedSamples) {
    plans_.resize(static_cast<std::size_t>(input.channels) * input.height);
  }
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

  // observation = E[o] of input row (c, y); returns Var(o), W values, and
  // adds the row's clipped readouts to `clipping`.
  const double* observe_with_variance(int c, int y, ReadoutClipping& clipping) {
    variance_.resize(observation_.size());
    pipeline_.observer_.load_row(pipeline_.input_.row(c, y), observer_scratch_);
    clipping +=
        pipeline_.observer_.observe(false, 0, c, y, observer_scratch_, observation_, variance_);
    return variance_.data();
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

  // restored[0 .. Wo) from the observation; by default into the worker's row.
  const double* restore(double* restored = nullptr) {
    double* out = restored != nullptr ? restored : row_.data();
    pipeline_.restorer_.restore(observation_.data(), restorer_scratch_, out);
    return out;
  }

 private:
  const RowPipeline& pipeline_;
  RowObserver::Scratch observer_scratch_;
  RowRestorer::Scratch restorer_scratch_;
  std::vector<double> observation_;  // W values
  std::vector<double> variance_;     // W values, Var(o) of the noise-free pass
  std::vector<double> row_;          // Wo values: an observed or restored row
};

template <typename PerRow>
void RowPipeline::for_each_row(const PerRow& per_row) const {
  const int height = input_.height;
  parallel_for(input_.channels * height, threads_, [&](int begin, int end) {
    Worker worker(*this);
    for (int r = begin; r < end; ++r) per_row(worker, r / height, r % height, r);
  });
}

bool RowPipeline::restore_all(std::optional<std::uint64_t> noise_seed, Image& restored,
                              ObservedRowSink* observed, ReadoutClipping* clipping) const {
  std::atomic<bool> observed_finite{true};
  std::atomic<std::uint64_t> saturated{0};
  std::atomic<std::uint64_t> near_zero{0};
  for_each_row([&](Worker& worker, int c, int y, int r) {
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

NoiseFreeRun RowPipeline::noise_free_pass(int first, int end) const {
  const int rows = input_.channels * input_.height;
  const int wa = geometry_.observed_width;
  const int h = geometry_.half_blur;
  // Blocks of rows fixed by the image alone, at most kVarianceBlocks of them.
  constexpr int kVarianceBlocks = 64;
  const int blocks = std::min(rows, kVarianceBlocks);
  std::vector<double> row_errors(static_cast<std::size_t>(rows));
  std::vector<double> block_sums(static_cast<std::size_t>(blocks) * wa, 0.0);
  std::vector<ReadoutClipping> block_clipping(static_cast<std::size_t>(blocks));
  parallel_for(blocks, threads_, [&](int block_begin, int block_end) {
    Worker worker(*this);
    for (int b = block_begin; b < block_end; ++b) {
      double* sums = block_sums.data() + static_cast<std::ptrdiff_t>(b) * wa;
      const auto row_begin = static_cast<int>(static_cast<long long>(rows) * b / blocks);
      const auto row_end = static_cast<int>(static_cast<long long>(rows) * (b + 1) / blocks);
      for (int r = row_begin; r < row_end; ++r) {
        const int c = r / input_.height;
        const int y = r % input_.height;
        const double* variance =
            worker.observe_with_variance(c, y, block_clipping[static_cast<std::size_t>(b)]) +
            h;  // crop column 0
        for (int j = 0; j < wa; ++j) sums[j] += variance[j];
        row_errors[r] = row_squared_error(input_.row(c, y) + 3 * h, worker.restore(), first, end);
      }
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
  // S(j) = sum over the blocks, in order
  run.crop_variance_sums.assign(static_cast<std::size_t>(wa), 0.0);
  for (int b = 0; b < blocks; ++b) {
    const double* sums = block_sums.data() + static_cast<std::ptrdiff_t>(b) * wa;
    for (int j = 0; j < wa; ++j) run.crop_variance_sums[j] += sums[j];
  }
  return run;
}

}  // namespace fss
