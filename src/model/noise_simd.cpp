// Batched Box-Muller. This file alone is compiled with -ffast-math (see
// CMakeLists.txt): that is what makes glibc declare its
// vector math library (libmvec) so that the loops below call vector log, sin
// and cos. Only compile flags are affected: the link does not use -ffast-math,
// so the process's floating-point environment (no flush-to-zero) is unchanged.
// Inputs are finite (u1 in (0, 1], u2 in [0, 1)), where fast-math's
// assumptions hold.
//
// Two builds of the same loops: 4-wide AVX2 (libmvec's _ZGVdN4v_*), taken
// when the processor has AVX2, and 2-wide SSE (_ZGVbN2v_*) otherwise. Our
// loops hold no a * b + c, so neither build can fuse a multiply-add;
// libmvec's variants themselves may differ in the last bits (so do its SSE4.1
// and SSE2 variants, which glibc already picks by processor); the per-frame
// sampler rounds its photon counts to integers, which hides such differences
// unless lambda + sqrt(lambda) N is within about 1e-13 of a half-integer
// (docs/method.md §3). The result is deterministic for a given binary and
// processor. The aggregated sampler, whose normal is not rounded, uses
// box_muller_portable (noise_stream.h) instead.
// glibc declares libmvec to GCC only: clang (the sanitizer and fuzzing
// builds) calls the scalar log, sin and cos, as accurate; the Poisson
// variates are rounded to integers.
#include <cmath>
#include <cstddef>
#include <vector>

#include "model/noise_stream.h"

namespace fss {

namespace {

// Three separate loops: fused, GCC turns sin and cos into one sincos call,
// which has no vector variant, and the loop stays scalar. Inlined into each
// build below, so that each is vectorized for its own instruction set.
[[gnu::always_inline]] inline void box_muller_loops(const double* u1, const double* u2, double* z,
                                                    std::size_t pairs, double* __restrict r,
                                                    double* __restrict c, double* __restrict s) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  for (std::size_t j = 0; j < pairs; ++j) r[j] = std::sqrt(-2.0 * std::log(u1[j]));
  for (std::size_t j = 0; j < pairs; ++j) c[j] = r[j] * std::cos(kTwoPi * u2[j]);
  for (std::size_t j = 0; j < pairs; ++j) s[j] = r[j] * std::sin(kTwoPi * u2[j]);
  // z[2j] = sqrt(-2 ln u1) cos(2 pi u2), z[2j+1] = sqrt(-2 ln u1) sin(2 pi u2)
  for (std::size_t j = 0; j < pairs; ++j) {
    z[2 * j] = c[j];
    z[2 * j + 1] = s[j];
  }
}

void box_muller_sse(const double* u1, const double* u2, double* z, std::size_t pairs, double* r,
                    double* c, double* s) {
  box_muller_loops(u1, u2, z, pairs, r, c, s);
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define FSS_BOX_MULLER_AVX2 1
[[gnu::target("avx2")]] void box_muller_avx2(const double* u1, const double* u2, double* z,
                                             std::size_t pairs, double* r, double* c, double* s) {
  box_muller_loops(u1, u2, z, pairs, r, c, s);
}
#endif

}  // namespace

void box_muller_batch(const double* u1, const double* u2, double* z, std::size_t pairs) {
  thread_local std::vector<double> radius, cosine, sine;
  radius.resize(pairs);
  cosine.resize(pairs);
  sine.resize(pairs);
#ifdef FSS_BOX_MULLER_AVX2
  static const bool kAvx2 = __builtin_cpu_supports("avx2");
  if (kAvx2) {
    box_muller_avx2(u1, u2, z, pairs, radius.data(), cosine.data(), sine.data());
    return;
  }
#endif
  box_muller_sse(u1, u2, z, pairs, radius.data(), cosine.data(), sine.data());
}

}  // namespace fss
