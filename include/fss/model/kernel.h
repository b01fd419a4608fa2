// Invertibility and noise amplification of a code's transfer function.
#pragma once

#include <span>

namespace fss {

struct KernelAnalysis {
  double k0 = 0.0;          // K(0) = dt * sum alpha_k
  double min_abs = 0.0;     // min |K(xi)| over xi in [-pi, pi]
  double min_abs_xi = 0.0;  // where it is reached (the non-negative one of a +/- pair)
  bool invertible = false;  // min_abs > kInvertibilityTolerance * dt * sum |alpha_k|
};

// Relative level below which |K| counts as a zero on the band.
inline constexpr double kInvertibilityTolerance = 1e-6;

// Scans |K| densely over [-pi, pi] and refines every local minimum by golden
// section search, so a zero between samples is found.
KernelAnalysis analyze_kernel(std::span<const double> gains, double velocity, double dt);

// M = mean over the N bins of an N-point DFT of 1 / |K(xi)|^2: the noise
// amplification of the inverse filter on that grid. Infinite if a bin has K = 0.
double mean_inverse_power(std::span<const double> gains, double velocity, double dt, int n);

}  // namespace fss
