#include "campaign/student_t.h"

#include <algorithm>
#include <cmath>

namespace fss::student_t {

namespace {

// The continued fraction of the incomplete beta function, by the modified Lentz method:
// I_x(a, b) = x^a (1 - x)^b / (a B(a, b)) / (1 + d_1 / (1 + d_2 / (1 + ...))), with
// d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)) and
// d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)); it converges fast for x < (a + 1) / (a + b + 2).
double beta_continued_fraction(double x, double a, double b) {
  constexpr double kTiny = 1e-300;
  const auto guard = [](double v) { return std::abs(v) < kTiny ? kTiny : v; };
  double c = 1.0;
  double d = 1.0 / guard(1.0 - (a + b) * x / (a + 1.0));
  double f = d;
  for (int m = 1; m <= 20000; ++m) {
    const double two_m = 2.0 * m;
    const double even = m * (b - m) * x / ((a + two_m - 1.0) * (a + two_m));
    d = 1.0 / guard(1.0 + even * d);
    c = guard(1.0 + even / c);
    f *= d * c;
    const double odd = -(a + m) * (a + b + m) * x / ((a + two_m) * (a + two_m + 1.0));
    d = 1.0 / guard(1.0 + odd * d);
    c = guard(1.0 + odd / c);
    const double step = d * c;
    f *= step;
    if (std::abs(step - 1.0) < 1e-15) break;
  }
  return f;
}

// The regularized incomplete beta function I_x(a, b), 0 <= x <= 1, with
// I_x(a, b) = 1 - I_{1-x}(b, a) where the fraction would converge slowly.
double incomplete_beta(double x, double a, double b) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) {
    return std::exp(log_front) * beta_continued_fraction(x, a, b) / a;
  }
  return 1.0 - std::exp(log_front) * beta_continued_fraction(1.0 - x, b, a) / b;
}

}  // namespace

// P(|T| > t) = I_{nu / (nu + t^2)}(nu / 2, 1 / 2).
double two_sided_tail(double t, double nu) {
  nu = std::min(nu, kMaxDegreesOfFreedom);
  if (!(t > 0.0)) return 1.0;
  if (std::isinf(t)) return 0.0;
  const double t2 = t * t;
  // nu / (nu + t^2), written so that it does not round to 1 for small t^2 / nu.
  const double x = 1.0 / (1.0 + t2 / nu);
  return incomplete_beta(x, 0.5 * nu, 0.5);
}

// By bisection in log t, the tail decreasing in t: to a relative 1e-12.
double two_sided_quantile(double p, double nu) {
  if (p >= 1.0) return 0.0;
  double low = 0.0, high = 1.0;
  while (two_sided_tail(high, nu) > p && high < 1e300) {
    low = high;
    high *= 16.0;
  }
  for (int i = 0; i < 400 && high - low > 1e-12 * high; ++i) {
    const double middle = low > 0.0 ? std::sqrt(low * high) : 0.5 * high;
    (two_sided_tail(middle, nu) > p ? low : high) = middle;
  }
  return high;
}

}  // namespace fss::student_t
