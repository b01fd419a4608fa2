#include "pipeline/fitted_restoration.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <utility>

#include "core/fft.h"
#include "core/golden_section.h"
#include "core/parallel.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/prediction.h"
#include "pipeline/noise_weights.h"
#include "pipeline/plan_core.h"
#include "pipeline/restoration_filter.h"
#include "pipeline/row_pipeline.h"

namespace fss {

namespace {

// Rows are summed in at most this many fixed blocks, in order: the same bits
// for any thread count.
constexpr int kBlocks = 64;

// The buffers of one block of rows.
struct RowScratch {
  explicit RowScratch(const RowObserver& observer, int width, int mirror)
      : observer(observer),
        observation(static_cast<std::size_t>(width)),
        variance(static_cast<std::size_t>(width)),
        workspace(mirror) {}
  RowObserver::Scratch observer;
  std::vector<double> observation;
  std::vector<double> variance;
  RowFFT::Workspace workspace;
};

// sums[k] += |DFT_N(mirror of crop)|^2, k in [0, N/2] (the mirror extension of docs/method.md §4).
void add_mirror_power(const double* crop, int wa, RowFFT::Workspace& workspace, double* sums) {
  const std::span<double> row = workspace.real();
  std::copy(crop, crop + wa, row.begin());
  std::reverse_copy(crop, crop + wa, row.begin() + wa);
  RowFFT::for_size(2 * wa).forward(workspace);
  const std::span<const Complex> spectrum = workspace.spectrum();
  for (std::size_t k = 0; k < spectrum.size(); ++k) sums[k] += std::norm(spectrum[k]);
}

// The sum over the rows (c, y) of per_row(c, y, scratch, sums), `width` sums
// each, made in fixed blocks of rows summed in block order.
template <typename PerRow>
std::vector<double> sum_over_rows(const Image& input, const RowObserver& observer, int mirror,
                                  int threads, int width, const PerRow& per_row) {
  const int rows = input.channels * input.height;
  const int blocks = std::min(rows, kBlocks);
  std::vector<double> block_sums(static_cast<std::size_t>(blocks) * width, 0.0);
  parallel_for_each(blocks, threads, [&](int b) {
    RowScratch scratch(observer, input.width, mirror);
    double* sums = block_sums.data() + static_cast<std::ptrdiff_t>(b) * width;
    const auto first = static_cast<int>(static_cast<long long>(rows) * b / blocks);
    const auto end = static_cast<int>(static_cast<long long>(rows) * (b + 1) / blocks);
    for (int r = first; r < end; ++r) per_row(r / input.height, r % input.height, scratch, sums);
  });
  std::vector<double> total(static_cast<std::size_t>(width), 0.0);
  for (int b = 0; b < blocks; ++b) {
    for (int k = 0; k < width; ++k) total[k] += block_sums[static_cast<std::size_t>(b) * width + k];
  }
  return total;
}

// The observer of the run (its snr, noise model and sensor).
RowObserver run_observer(const PlanCore& plan, const SimulationOptions& options) {
  return plan.observer().with_noise(observation_params(options, plan.geometry()));
}

// The minimum of f over t in [lo, hi]: the best of `points` equally spaced
// nodes, then golden-section search between its neighbours to `tolerance`.
template <typename F>
double minimize_on_interval(const F& f, double lo, double hi, int points, double tolerance) {
  const double step = (hi - lo) / (points - 1);
  int best = 0;
  double best_value = std::numeric_limits<double>::infinity();
  for (int i = 0; i < points; ++i) {
    const double value = f(lo + i * step);
    if (value < best_value) best = i, best_value = value;
  }
  const auto [t, value] =
      golden_section_minimum(f, lo + std::max(best - 1, 0) * step,
                             lo + std::min(best + 1, points - 1) * step, 200, tolerance);
  return value <= best_value ? t : lo + best * step;
}

// M and W(j) of `filter`, and its restorer.
FittedFilter finish(const PlanCore& plan, const SimulationOptions& options, FilterBins filter) {
  const Geometry& g = plan.geometry();
  FittedFilter fitted;
  fitted.m_amplification = filter_mean_power(filter.h, g.mirror_width);
  if (options.noise != NoiseModel::kNone) {
    fitted.noise_weights =
        noise_energy_weights(g, filter_impulse_response(filter.h, g.mirror_width),
                             plan.windows().rmse_first, plan.windows().rmse_end);
  }
  fitted.restorer.emplace(g, std::move(filter));
  fitted.summary.options = options.restoration;
  return fitted;
}

double restore_velocity(const SimulationOptions& options) {
  return options.restore_velocity_px_per_slot.value_or(options.velocity_px_per_slot);
}

// Wiener with the oracle prior: S the mean |DFT|^2 of the ground truth's mirror-extended rows
// aligned with the observed crop (input columns [h, h + Wa)), N = 2 Wa sigma^2 with sigma^2 the
// model's exact per-pixel variance averaged over the observed crop.
FittedFilter oracle_wiener(const PlanCore& plan, const SimulationOptions& options,
                           const Image& input, const ShutterCode& code) {
  const Geometry& g = plan.geometry();
  const int wa = g.observed_width;
  const int bins = g.mirror_width / 2 + 1;
  const bool noisy = options.noise != NoiseModel::kNone;
  const RowObserver observer = run_observer(plan, options);
  const std::vector<double> sums =
      sum_over_rows(input, observer, g.mirror_width, options.threads, bins + 1,
                    [&](int c, int y, RowScratch& s, double* row_sums) {
                      add_mirror_power(input.row(c, y) + g.half_blur, wa, s.workspace, row_sums);
                      if (!noisy) return;
                      observer.load_row(input.row(c, y), s.observer);
                      observer.observe(false, 0, c, y, s.observer, s.observation, s.variance);
                      for (int j = 0; j < wa; ++j) row_sums[bins] += s.variance[g.half_blur + j];
                    });
  const double rows = static_cast<double>(input.height) * input.channels;
  std::vector<double> signal(sums.begin(), sums.begin() + bins);
  for (double& s : signal) s /= rows;
  const double variance = sums[static_cast<std::size_t>(bins)] / (rows * wa);
  FittedFilter fitted = finish(plan, options,
                               wiener_filter_bins(code.gains, restore_velocity(options), options.dt,
                                                  g.mirror_width, signal, 2.0 * wa * variance));
  fitted.summary.noise_variance = variance;
  return fitted;
}

// c of S = c |xi|^-gamma fitted to the calibration rows' mean power P_k = |K_k|^2 S_k + N in
// the log domain: the c minimising sum_k (log P_k - log(|K_k|^2 c |xi_k|^-gamma + N))^2 over
// the bins 0 < k < N/2 with P_k > 0. 0 when no bin qualifies.
double fit_power_law_level(const std::vector<double>& power, const std::vector<Complex>& k, int n,
                           double gamma, double noise) {
  std::vector<double> log_power, shape;  // log P_k and |K_k|^2 |xi_k|^-gamma
  double t0 = 0.0;
  int shaped = 0;
  for (std::size_t i = 1; i + 1 < power.size(); ++i) {
    if (!(power[i] > 0.0)) continue;
    log_power.push_back(std::log(power[i]));
    shape.push_back(std::norm(k[i]) *
                    std::pow(std::abs(bin_frequency(static_cast<int>(i), n)), -gamma));
    if (shape.back() > 0.0) t0 += log_power.back() - std::log(shape.back()), ++shaped;
  }
  if (shaped == 0) return 0.0;
  t0 /= shaped;  // the fit without noise
  const auto misfit = [&](double t) {
    const double c = std::exp(t);
    double sum = 0.0;
    for (std::size_t i = 0; i < shape.size(); ++i) {
      const double d = log_power[i] - std::log(shape[i] * c + noise);
      sum += d * d;
    }
    return sum;
  };
  return std::exp(minimize_on_interval(misfit, t0 - 40.0, t0 + 40.0, 81, 1e-6));
}

// Wiener with a power-law prior fitted to one calibration observation on streams of its own
// (kCalibrationChannel): sigma^2 the model's variance at the level m = mean(crop) / K(0)
// (observed_divisor) and c by fit_power_law_level; never the ground truth.
FittedFilter power_law_wiener(const PlanCore& plan, const SimulationOptions& options,
                              const Image& input, const ShutterCode& code) {
  const Geometry& g = plan.geometry();
  const int wa = g.observed_width;
  const int n = g.mirror_width;
  const int bins = n / 2 + 1;
  const bool noisy = options.noise != NoiseModel::kNone;
  const RowObserver observer = run_observer(plan, options);
  const std::vector<double> sums =
      sum_over_rows(input, observer, n, options.threads, bins + 1,
                    [&](int c, int y, RowScratch& s, double* row_sums) {
                      observer.load_row(input.row(c, y), s.observer);
                      observer.observe(noisy, options.seed, kCalibrationChannel + c, y, s.observer,
                                       s.observation);
                      const double* crop = s.observation.data() + g.half_blur;
                      add_mirror_power(crop, wa, s.workspace, row_sums);
                      for (int j = 0; j < wa; ++j) row_sums[bins] += crop[j];
                    });
  const double rows = static_cast<double>(input.height) * input.channels;
  std::vector<double> power(sums.begin(), sums.begin() + bins);
  for (double& p : power) p /= rows;
  const double level =
      std::max(sums[static_cast<std::size_t>(bins)] / (rows * wa) / plan.observed_divisor(), 0.0);
  const double v_r = restore_velocity(options);
  double variance = 0.0;
  if (noisy) {
    const double sigma =
        noise_sigma(level, code.gains, options.dt, options.mode, 1.0, options.snr, options.sensor);
    variance = sigma * sigma;
  }
  const double gamma = options.restoration.prior_exponent;
  const double c = fit_power_law_level(
      power, transfer_function_bins(code.gains, v_r, options.dt, n), n, gamma, 2.0 * wa * variance);
  FittedFilter fitted =
      finish(plan, options,
             wiener_filter_bins(code.gains, v_r, options.dt, n, power_law_signal_power(n, gamma, c),
                                2.0 * wa * variance));
  fitted.summary.prior_level = c / n;  // per bin of the n-point DFT -> per radian/pixel
  fitted.summary.noise_variance = variance;
  return fitted;
}

// The noise-free observed crops of every row and S(j), for the Tikhonov search.
struct NoiseFreeCrops {
  std::vector<double> crops;  // row r = c H + y at r Wa
  std::vector<double> variance_sums;
};

NoiseFreeCrops noise_free_crops(const PlanCore& plan, const SimulationOptions& options,
                                const Image& input) {
  const Geometry& g = plan.geometry();
  const int wa = g.observed_width;
  const bool noisy = options.noise != NoiseModel::kNone;
  const RowObserver observer = run_observer(plan, options);
  NoiseFreeCrops result;
  result.crops.resize(static_cast<std::size_t>(input.height) * input.channels * wa);
  result.variance_sums = sum_over_rows(
      input, observer, g.mirror_width, options.threads, wa,
      [&](int c, int y, RowScratch& s, double* row_sums) {
        observer.load_row(input.row(c, y), s.observer);
        observer.observe(false, 0, c, y, s.observer, s.observation,
                         noisy ? std::span<double>(s.variance) : std::span<double>());
        const double* crop = s.observation.data() + g.half_blur;
        std::copy(crop, crop + wa,
                  result.crops.begin() + static_cast<std::ptrdiff_t>(c * input.height + y) * wa);
        if (noisy) {
          for (int j = 0; j < wa; ++j) row_sums[j] += s.variance[g.half_blur + j];
        }
      });
  return result;
}

// E[sum over the RMSE window of d^2] / count for the Tikhonov filter of `lambda`: the noise-free
// error of its restoration of the crops plus sum_j W(j) S(j) (docs/method.md §6b).
double tikhonov_expected_mse(const PlanCore& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code,
                             const NoiseFreeCrops& data, double lambda) {
  const Geometry& g = plan.geometry();
  const int first = plan.windows().rmse_first;
  const int end = plan.windows().rmse_end;
  FilterBins filter = tikhonov_filter_bins(code.gains, restore_velocity(options), options.dt,
                                           g.mirror_width, lambda);
  double noise = 0.0;
  if (options.noise != NoiseModel::kNone) {
    const std::vector<double> w =
        noise_energy_weights(g, filter_impulse_response(filter.h, g.mirror_width), first, end);
    for (std::size_t j = 0; j < w.size(); ++j) noise += w[j] * data.variance_sums[j];
  }
  const RowRestorer restorer(g, std::move(filter));
  const int rows = input.height * input.channels;
  std::vector<double> row_errors(static_cast<std::size_t>(rows));
  parallel_for(rows, options.threads, [&](int begin, int stop) {
    RowRestorer::Scratch scratch(restorer);
    std::vector<double> restored(static_cast<std::size_t>(g.output_width));
    for (int r = begin; r < stop; ++r) {
      restorer.restore_crop(data.crops.data() + static_cast<std::ptrdiff_t>(r) * g.observed_width,
                            scratch, restored.data());
      row_errors[static_cast<std::size_t>(r)] =
          row_squared_error(input.row(r / input.height, r % input.height) + 3 * g.half_blur,
                            restored.data(), first, end);
    }
  });
  double total = noise;
  for (const double e : row_errors) total += e;
  return total / (static_cast<double>(end - first) * rows);
}

// Tikhonov at the lambda in [kMinRegularization, kMaxRegularization] minimising the run's exact
// expected error (an oracle: it knows the image): a grid of two nodes a decade in log10 lambda,
// then golden-section search to 1e-3 in log10 lambda.
FittedFilter optimal_tikhonov(const PlanCore& plan, const SimulationOptions& options,
                              const Image& input, const ShutterCode& code) {
  const NoiseFreeCrops data = noise_free_crops(plan, options, input);
  const double lo = std::log10(kMinRegularization);
  const double hi = std::log10(kMaxRegularization);
  const double t = minimize_on_interval(
      [&](double x) {
        return tikhonov_expected_mse(plan, options, input, code, data, std::pow(10.0, x));
      },
      lo, hi, static_cast<int>(2 * (hi - lo)) + 1, 1e-3);
  const double lambda = std::pow(10.0, t);
  FittedFilter fitted =
      finish(plan, options,
             tikhonov_filter_bins(code.gains, restore_velocity(options), options.dt,
                                  plan.geometry().mirror_width, lambda));
  fitted.summary.regularization = lambda;
  return fitted;
}

}  // namespace

FittedFilter fit_restoration(const PlanCore& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code) {
  if (options.restoration.method == RestorationMethod::kTikhonov) {
    return optimal_tikhonov(plan, options, input, code);
  }
  if (options.restoration.prior == PriorKind::kOracle) {
    return oracle_wiener(plan, options, input, code);
  }
  return power_law_wiener(plan, options, input, code);
}

std::size_t fitted_restoration_bytes(const SimulationOptions& options, int observed_width,
                                     int height, int channels) {
  const RestorationOptions& r = options.restoration;
  if (r.method != RestorationMethod::kTikhonov || r.regularization) return 0;
  // the noise-free crops of the search
  return sizeof(double) * static_cast<std::size_t>(observed_width) * height * channels;
}

}  // namespace fss
