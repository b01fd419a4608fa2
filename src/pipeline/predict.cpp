#include "pipeline/predict.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/prediction.h"
#include "pipeline/noise_weights.h"

namespace fss {

// m: the mean of input columns [first, end), per channel, then averaged over
// the channels (equal pixel counts).
double window_mean(const Image& image, int first, int end) {
  double sum = 0.0;
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      for (int x = first; x < end; ++x) sum += image.at(c, y, x);
    }
  }
  return sum / (static_cast<double>(end - first) * image.height * image.channels);
}

// sum_j W(j) S(j) / (rows * channels * window width): the noise part of
// E[MSE] over the RMSE window (docs/method.md §6b).
double exact_noise_power(const SimulationReport& report, const std::vector<double>& w,
                         const NoiseFreeRun& run) {
  const std::vector<double>& s = run.crop_variance_sums;
  const int wa = report.geometry.observed_width;
  if (s.size() != static_cast<std::size_t>(wa)) {
    throw_usage_error("the exact prediction needs S(j) for each of the " + std::to_string(wa) +
                      " observed-crop columns, but the noise-free run has " +
                      std::to_string(s.size()));
  }
  double total = 0.0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    if (w[j] != 0.0) total += w[j] * s[j];  // a column without weight adds 0, even for S = inf
  }
  const double count =
      static_cast<double>(report.rmse_end - report.rmse_first) * report.height * report.channels;
  return total / count;
}

namespace {

// The prediction, with M and W(j) from `m_amplification()` and
// `noise_weights()` (called only when needed).
template <typename M, typename W>
Prediction predict_with(const SimulationReport& report, const Image& input,
                        const NoiseFreeRun& noise_free, const M& m_amplification,
                        const W& noise_weights) {
  const SimulationOptions& options = report.options;
  const bool noisy = options.noise != NoiseModel::kNone;
  const double r0 = noise_free.rmse;
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Prediction p;
  // A regularised filter is bounded: its error is finite for every code (docs/method.md §12).
  const bool inverse = options.restoration.method == RestorationMethod::kInverse;
  p.finite = report.kernel.invertible || !inverse;
  p.window_mean = window_mean(input, report.output_first_column() + report.rmse_first,
                              report.output_first_column() + report.rmse_end);
  p.q = noise_gain(report.gains, options.dt, options.mode);
  p.m_amplification = p.finite ? m_amplification() : kInfinity;
  p.rmse_noise_free = r0;
  // The inverse filter's figure of merit; a regularised one's needs a prior (code analyze).
  p.snr_level100 = inverse ? snr_level100(report.gains, options.dt, options.mode, p.m_amplification,
                                          options.snr, options.sensor)
                           : 0.0;
  // A clipping sensor breaks the linear model of the variance terms (docs/method.md §10).
  p.exact = noise_free.saturated_readouts == 0 && noise_free.near_zero_readouts == 0;
  if (!p.finite) {
    p.noise = p.rmse = p.sigma = p.rmse_stationary = kInfinity;
    return p;
  }
  // Stationary (§6): E[RMSE^2] ~ RMSE_0^2 + m Q (100 / snr^2) M
  p.sigma = noisy ? noise_sigma(p.window_mean, report.gains, options.dt, options.mode,
                                p.m_amplification, options.snr, options.sensor)
                  : 0.0;
  p.rmse_stationary = std::sqrt(r0 * r0 + p.sigma * p.sigma);
  // Exact (§6b): E[MSE] = RMSE_0^2 + sum_j W(j) S(j) / count
  const double noise_power = noisy ? exact_noise_power(report, noise_weights(), noise_free) : 0.0;
  p.noise = std::sqrt(noise_power);
  p.rmse = std::sqrt(r0 * r0 + noise_power);
  return p;
}

}  // namespace

Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free) {
  const SimulationOptions& o = report.options;
  const double v_r = o.restore_velocity_px_per_slot.value_or(o.velocity_px_per_slot);
  return predict_with(
      report, input, noise_free,
      [&] { return mean_inverse_power(report.gains, v_r, o.dt, report.geometry.mirror_width); },
      [&] {
        return noise_energy_weights(report.geometry, report.gains, v_r, o.dt, report.rmse_first,
                                    report.rmse_end);
      });
}

Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free, double m_amplification,
                   const std::vector<double>& noise_weights) {
  return predict_with(
      report, input, noise_free, [&] { return m_amplification; },
      [&]() -> const std::vector<double>& { return noise_weights; });
}

}  // namespace fss
