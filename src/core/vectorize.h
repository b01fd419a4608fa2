// Loops compiled twice, for AVX2 and for the baseline instruction set.
// Internal to the library.
//
// The row loops of the samplers and of the observation are written to
// vectorize; run_vectorized(kernel) runs them, inlined, in a copy compiled
// for AVX2 (4 doubles a vector) when the processor has it, else in the
// baseline SSE2 copy (2 doubles). Only AVX2, never FMA: GCC contracts a * b +
// c into a fused multiply-add when FMA is enabled (even in ISO C++ mode),
// which rounds once instead of twice. Without it every operation in the
// kernels (max, +, *, /, sqrt, comparisons, selections, integer to double
// conversions) is correctly rounded, so both copies give the same bits.
#pragma once

namespace fss::detail {

inline bool processor_has_avx2() {
#if defined(__GNUC__) && defined(__x86_64__)
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  return has_avx2;
#else
  return false;
#endif
}

template <typename Kernel>
void run_baseline(const Kernel& kernel) {
  kernel();
}

#if defined(__GNUC__) && defined(__x86_64__)
template <typename Kernel>
[[gnu::target("avx2")]] void run_avx2(const Kernel& kernel) {
  kernel();
}
#else
template <typename Kernel>
void run_avx2(const Kernel& kernel) {
  kernel();
}
#endif

// kernel: a lambda marked __attribute__((always_inline)), so that each copy
// compiles its loops for its own instruction set. Locals (pointers declared
// __restrict, scalars copied) rather than captured references let the loops
// vectorize.
template <typename Kernel>
void run_vectorized(const Kernel& kernel) {
  if (processor_has_avx2()) {
    run_avx2(kernel);
  } else {
    run_baseline(kernel);
  }
}

}  // namespace fss::detail
