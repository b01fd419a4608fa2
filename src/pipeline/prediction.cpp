#include "fss/pipeline/prediction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/scaled_math.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "pipeline/noise_weights.h"

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
  // sigma^2 = ((max(m, 0) / 100) V_photon + (V_100 - V_photon)) M: the readouts' terms do not
  // scale with the level m (docs/method.md §10).
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

}  // namespace fss
