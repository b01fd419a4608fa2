// Quotients and square roots of products whose plain formula can leave the
// range of doubles (overflow to inf, underflow to 0, then inf - inf or 0 * inf
// as NaN) although the result itself is in range: snr and dt run from 1e-100
// to 1e100, so lambda2 = snr^2 / 100 from 1e-202 to 1e198 and lambda2^2 past
// both ends. Each function computes the plain formula while its intermediate
// is a normal double (the same bits as the formula written out), and a scaled
// form otherwise. Not part of the public interface.
#pragma once

#include <cmath>
#include <initializer_list>
#include <limits>

namespace fss::detail {

// True for a finite double that is not subnormal or 0.
inline bool is_normal_positive(double x) {
  return x >= std::numeric_limits<double>::min() && x <= std::numeric_limits<double>::max();
}

// x / (a * a) for a > 0 and x >= 0: as written while a * a is normal, else
// x / a / a (0 for x = 0, never 0 / 0).
inline double divide_by_square(double x, double a) {
  const double square = a * a;
  if (is_normal_positive(square)) return x / square;
  return x / a / a;
}

// sqrt(f_1 * f_2 * ... * f_n) of factors >= 0 (+inf allowed): the product
// in the order given while it is normal, else 0 when a factor is 0 and the
// product of the square roots otherwise (+inf only when the result is).
inline double sqrt_of_product(std::initializer_list<double> factors) {
  double product = 1.0;
  for (const double f : factors) product *= f;
  if (is_normal_positive(product)) return std::sqrt(product);
  double root = 1.0;
  for (const double f : factors) {
    if (f == 0.0) return 0.0;
    root *= std::sqrt(f);
  }
  return root;
}

}  // namespace fss::detail
