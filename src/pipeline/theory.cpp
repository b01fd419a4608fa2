#include "fss/pipeline/theory.h"

#include <cmath>
#include <limits>

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

}  // namespace fss
