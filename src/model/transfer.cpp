#include "fss/model/transfer.h"

#include <cmath>

namespace fss {

double sinc_h(double theta) {
  const double half = 0.5 * theta;
  // Below 1e-4 the series 1 - x^2/6 + x^4/120 is exact to double precision.
  if (std::abs(half) < 1e-4) {
    const double h2 = half * half;
    return 1.0 - h2 / 6.0 + h2 * h2 / 120.0;
  }
  return std::sin(half) / half;
}

Complex transfer_function(std::span<const double> gains, double velocity, double dt, double xi) {
  const double theta = xi * velocity * dt;
  // sum_k alpha_k z^k with z = exp(-i theta), by Horner's scheme.
  const Complex z = std::polar(1.0, -theta);
  Complex sum = 0.0;
  for (auto k = gains.size(); k-- > 0;) sum = sum * z + gains[k];
  // K = dt sinc_h(theta) exp(-i theta / 2) sum_k alpha_k exp(-i theta k)
  return dt * sinc_h(theta) * std::polar(1.0, -0.5 * theta) * sum;
}

double bin_frequency(int i, int n) {
  const int f = (2 * i < n) ? i : i - n;
  return 2.0 * M_PI * static_cast<double>(f) / static_cast<double>(n);
}

std::vector<Complex> transfer_function_bins(std::span<const double> gains, double velocity,
                                            double dt, int n) {
  std::vector<Complex> bins(static_cast<std::size_t>(n / 2 + 1));
  for (int i = 0; i <= n / 2; ++i) {
    bins[i] = transfer_function(gains, velocity, dt, bin_frequency(i, n));
  }
  return bins;
}

std::vector<Complex> slot_transfer_function_bins(int k, double velocity, double dt, int n) {
  std::vector<Complex> bins(static_cast<std::size_t>(n / 2 + 1));
  for (int i = 0; i <= n / 2; ++i) {
    const double theta = bin_frequency(i, n) * velocity * dt;
    // K_k = dt sinc_h(theta) exp(-i theta (k + 1/2))
    bins[i] = dt * sinc_h(theta) * std::polar(1.0, -theta * (k + 0.5));
  }
  return bins;
}

}  // namespace fss
