// Batched Box-Muller. This file alone is compiled with -ffast-math (see
// CMakeLists.txt): that is what makes glibc declare its
// vector math library (libmvec) so that the loop below calls vector log, sin
// and cos. Only compile flags are affected: the link does not use -ffast-math,
// so the process's floating-point environment (no flush-to-zero) is unchanged.
// Inputs are finite (u1 in (0, 1], u2 in [0, 1)), where fast-math's
// assumptions hold. The result is deterministic for a given binary.
// glibc declares libmvec to GCC only: clang (the sanitizer and fuzzing
// builds) calls the scalar log, sin and cos, slower but as accurate; the
// Poisson variates are rounded to integers, and on camera.png the two
// builds write the same report.json.
#include <cmath>
#include <cstddef>
#include <vector>

#include "fss/model/noise.h"

namespace fss {

void box_muller_batch(const double* u1, const double* u2, double* z, std::size_t pairs) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  // Three separate loops: fused, GCC turns sin and cos into one sincos call,
  // which has no vector variant, and the loop stays scalar.
  thread_local std::vector<double> radius, cosine, sine;
  radius.resize(pairs);
  cosine.resize(pairs);
  sine.resize(pairs);
  double* __restrict r = radius.data();
  double* __restrict c = cosine.data();
  double* __restrict s = sine.data();
  for (std::size_t j = 0; j < pairs; ++j) r[j] = std::sqrt(-2.0 * std::log(u1[j]));
  for (std::size_t j = 0; j < pairs; ++j) c[j] = r[j] * std::cos(kTwoPi * u2[j]);
  for (std::size_t j = 0; j < pairs; ++j) s[j] = r[j] * std::sin(kTwoPi * u2[j]);
  // z[2j] = sqrt(-2 ln u1) cos(2 pi u2), z[2j+1] = sqrt(-2 ln u1) sin(2 pi u2)
  for (std::size_t j = 0; j < pairs; ++j) {
    z[2 * j] = c[j];
    z[2 * j + 1] = s[j];
  }
}

}  // namespace fss
