#include "fss/pipeline/prediction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/scaled_math.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/noise_weights.h"
#include "fss/pipeline/simulate.h"

namespace fss {

double noise_gain(std::span<const double> gains, double dt, ShutterMode mode) {
  double sum = 0.0;
  for (const double g : gains) sum += mode == ShutterMode::kNumerical ? g * g : g;
  return dt * sum;  // Q = dt sum alpha^2 (numerical) or dt sum alpha (analog)
}

double noise_sigma(double mean_level, double q, double m_amplification, double snr) {
  if (!std::isfinite(m_amplification)) return std::numeric_limits<double>::infinity();
  // sigma^2 = max(m, 0) Q (100 / snr^2) M: a negative landscape gives no photons
  return detail::sqrt_of_product(
      {std::max(mean_level, 0.0), q, 100.0 / (snr * snr), m_amplification});
}

double snr_level100(double q, double m_amplification, double snr) {
  if (!std::isfinite(m_amplification)) return 0.0;
  return 100.0 / noise_sigma(100.0, q, m_amplification, snr);
}

double noise_sigma(double mean_level, std::span<const double> gains, double dt, ShutterMode mode,
                   double m_amplification, double snr, const SensorModel& sensor) {
  if (!sensor.enabled()) {
    return noise_sigma(mean_level, noise_gain(gains, dt, mode), m_amplification, snr);
  }
  if (!std::isfinite(m_amplification)) return std::numeric_limits<double>::infinity();
  // sigma^2 = ((max(m, 0) / 100) V_photon + (V_100 - V_photon)) M
  const double photon = level100_observation_variance(gains, dt, mode, snr, SensorModel());
  const double with_sensor = level100_observation_variance(gains, dt, mode, snr, sensor);
  // V_100 - V_photon is the readouts' part: infinite with V_100 (never inf - inf).
  const double readouts = std::isinf(with_sensor) ? with_sensor : with_sensor - photon;
  const double photons = mean_level > 0.0 ? mean_level / 100.0 * photon : 0.0;
  return detail::sqrt_of_product({photons + readouts, m_amplification});
}

double snr_level100(std::span<const double> gains, double dt, ShutterMode mode,
                    double m_amplification, double snr, const SensorModel& sensor) {
  if (!sensor.enabled()) {
    return snr_level100(noise_gain(gains, dt, mode), m_amplification, snr);
  }
  if (!std::isfinite(m_amplification)) return 0.0;
  // 100 / sqrt(V_100 M)
  return 100.0 /
         detail::sqrt_of_product(
             {level100_observation_variance(gains, dt, mode, snr, sensor), m_amplification});
}

namespace {

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
  p.finite = report.kernel.invertible;
  p.window_mean = window_mean(input, report.output_first_column() + report.rmse_first,
                              report.output_first_column() + report.rmse_end);
  p.q = noise_gain(report.gains, options.dt, options.mode);
  p.m_amplification = p.finite ? m_amplification() : kInfinity;
  p.rmse_noise_free = r0;
  p.snr_level100 = snr_level100(report.gains, options.dt, options.mode, p.m_amplification,
                                options.snr, options.sensor);
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
                   const NoiseFreeRun& noise_free, const SimulationPlan& plan) {
  return predict_with(
      report, input, noise_free, [&] { return plan.m_amplification(); },
      [&]() -> const std::vector<double>& { return plan.noise_weights(); });
}

}  // namespace fss
