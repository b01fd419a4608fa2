#include "fss/model/kernel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/golden_section.h"
#include "fss/model/transfer.h"

namespace fss {

namespace {
// Golden-section search for the minimum of |K| on [a, b]; returns (xi, |K|).
std::pair<double, double> refine_minimum(std::span<const double> gains, double velocity, double dt,
                                         double a, double b) {
  const auto f = [&](double xi) { return std::abs(transfer_function(gains, velocity, dt, xi)); };
  return golden_section_minimum(f, a, b, 80, 1e-15);
}
}  // namespace

double transfer_scale(std::span<const double> gains, double dt) {
  double abs_sum = 0.0;
  for (const double g : gains) abs_sum += std::abs(g);
  return dt * abs_sum;
}

double transfer_zero_level(double scale, double tolerance) { return tolerance * scale; }

bool transfer_vanishes(double abs_k, double scale, double tolerance) {
  return abs_k <= transfer_zero_level(scale, tolerance);
}

// Scans |K| densely and refines every local minimum by golden-section search, so that a zero
// between samples is found.
KernelAnalysis analyze_kernel(std::span<const double> gains, double velocity, double dt) {
  KernelAnalysis result;
  double sum = 0.0;
  for (const double g : gains) sum += g;
  result.k0 = dt * sum;
  const double scale = transfer_scale(gains, dt);

  // |K(-xi)| = |K(xi)| for real gains: scan [0, pi] only.
  const int intervals = std::max<int>(4096, 64 * static_cast<int>(gains.size()));
  std::vector<double> values(static_cast<std::size_t>(intervals) + 1);
  auto xi_of = [&](int j) { return M_PI * j / intervals; };
  for (int j = 0; j <= intervals; ++j) {
    values[j] = std::abs(transfer_function(gains, velocity, dt, xi_of(j)));
  }
  result.min_abs = std::numeric_limits<double>::infinity();
  for (int j = 0; j <= intervals; ++j) {
    const bool left_ok = j == 0 || values[j] <= values[j - 1];
    const bool right_ok = j == intervals || values[j] <= values[j + 1];
    if (!(left_ok && right_ok)) continue;
    if (values[j] < result.min_abs) {
      result.min_abs = values[j];
      result.min_abs_xi = xi_of(j);
    }
    const auto [xi, value] = refine_minimum(gains, velocity, dt, xi_of(std::max(j - 1, 0)),
                                            xi_of(std::min(j + 1, intervals)));
    if (value < result.min_abs) {
      result.min_abs = value;
      result.min_abs_xi = xi;
    }
  }
  result.invertible =
      scale > 0.0 && !transfer_vanishes(result.min_abs, scale, kInvertibilityTolerance);
  return result;
}

double mean_inverse_power(std::span<const double> gains, double velocity, double dt, int n) {
  const double scale = transfer_scale(gains, dt);
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const Complex k = transfer_function(gains, velocity, dt, bin_frequency(i, n));
    if (transfer_vanishes(std::abs(k), scale)) return std::numeric_limits<double>::infinity();
    sum += 1.0 / std::norm(k);
  }
  return sum / n;
}

}  // namespace fss
