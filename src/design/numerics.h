// Numerical pieces shared by the design modules (generate, analyze,
// optimize); not part of the public interface.
#pragma once

#include <cstdint>
#include <limits>
#include <random>

#include "fss/model/transfer.h"

namespace fss::design_detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Composite Simpson rule with `intervals` (even) sub-intervals.
template <typename F>
double simpson(F f, double a, double b, int intervals) {
  const double h = (b - a) / intervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

// 1 / sinc_h(theta) = (theta / 2) / sin(theta / 2), finite for |theta| < 2 pi.
inline double inverse_sinc_h(double theta) { return 1.0 / sinc_h(theta); }

// Portable uniform double in [0, 1) from a 64-bit generator
// (std::uniform_real_distribution's output is library-specific).
inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace fss::design_detail
