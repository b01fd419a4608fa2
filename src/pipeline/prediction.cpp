#include "fss/pipeline/prediction.h"

#include <cmath>
#include <limits>

#include "fss/model/kernel.h"
#include "fss/pipeline/simulate.h"

namespace fss {

double noise_gain(std::span<const double> gains, double dt, ShutterMode mode) {
  double sum = 0.0;
  for (const double g : gains) sum += mode == ShutterMode::kNumerical ? g * g : g;
  return dt * sum;  // Q = dt sum alpha^2 (numerical) or dt sum alpha (analog)
}

double noise_sigma(double mean_level, double q, double m_amplification, double snr) {
  if (!std::isfinite(m_amplification)) return std::numeric_limits<double>::infinity();
  // sigma^2 = m Q (100 / snr^2) M
  return std::sqrt(mean_level * q * (100.0 / (snr * snr)) * m_amplification);
}

double snr_level100(double q, double m_amplification, double snr) {
  if (!std::isfinite(m_amplification)) return 0.0;
  return 100.0 / noise_sigma(100.0, q, m_amplification, snr);
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

}  // namespace

Prediction predict(const SimulationReport& report, const Image& input, double rmse_noise_free) {
  const SimulationOptions& options = report.options;
  const double v_r = options.restore_velocity_px_per_slot.value_or(options.velocity_px_per_slot);
  const int offset = report.output_first_column();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Prediction p;
  p.finite = report.kernel.invertible;
  p.window_mean = window_mean(input, offset + report.rmse_first, offset + report.rmse_end);
  p.q = noise_gain(report.gains, options.dt, options.mode);
  p.m_amplification =
      p.finite ? mean_inverse_power(report.gains, v_r, options.dt, report.geometry.mirror_width)
               : kInfinity;
  p.rmse_noise_free = rmse_noise_free;
  p.snr_level100 = snr_level100(p.q, p.m_amplification, options.snr);
  p.sigma = options.noise == NoiseModel::kNone
                ? 0.0
                : noise_sigma(p.window_mean, p.q, p.m_amplification, options.snr);
  // E[RMSE^2] = RMSE_0^2 + m Q (100 / snr^2) M
  p.rmse = std::sqrt(rmse_noise_free * rmse_noise_free + p.sigma * p.sigma);
  if (!p.finite) {
    p.sigma = kInfinity;
    p.rmse = kInfinity;
  }
  return p;
}

}  // namespace fss
