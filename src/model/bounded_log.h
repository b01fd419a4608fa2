// Logarithms in plain arithmetic, for loops that must vectorize (the exact
// Poisson sampler's bulk slow test, exact_poisson.cpp): no library call, an
// absolute error below 1e-13 (1 + |result|) for a normal positive argument.
// Compiled without contraction into fused multiply-adds, like their callers.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace fss {

// 2 atanh(s) = ln((1 + s) / (1 - s)) = 2 (s + s^3 / 3 + ... + s^15 / 15),
// truncated below 2 |s|^17 / (17 (1 - s^2)) < 1.3e-14 for |s| <= 0.172.
inline double twice_atanh(double s) {
  const double s2 = s * s;
  const double tail = 1.0 / 9.0 + s2 * (1.0 / 11.0 + s2 * (1.0 / 13.0 + s2 * (1.0 / 15.0)));
  return 2.0 * s * (1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * tail))));
}

// ln y = e ln 2 + 2 atanh((m - 1) / (m + 1)), y = m 2^e, m in [sqrt(2) / 2, sqrt(2)].
inline double bounded_log(double y) {
  const auto bits = std::bit_cast<std::uint64_t>(y);
  double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);
  // e from the biased exponent without an integer conversion: 2^52 + n - 2^52.
  double e = std::bit_cast<double>((bits >> 52) | 0x4330000000000000ULL) - 0x1.0p52 - 1023.0;
  const bool high = m > std::numbers::sqrt2;
  m = high ? 0.5 * m : m;
  e = high ? e + 1.0 : e;
  return e * std::numbers::ln2 + twice_atanh((m - 1.0) / (m + 1.0));
}

// ln(1 + t) for |t| <= 1/4: 2 atanh(t / (2 + t)), |t / (2 + t)| <= 1/7.
inline double bounded_log1p_small(double t) { return twice_atanh(t / (2.0 + t)); }

// ln(1 + t), t > -1: bounded_log1p_small(t) for |t| <= 1/4, else
// bounded_log(1 + t), whose rounding of 1 + t costs below 2^-53 / 0.75.
inline double bounded_log1p(double t) {
  return std::abs(t) <= 0.25 ? bounded_log1p_small(t) : bounded_log(1.0 + t);
}

}  // namespace fss
