// Invertibility and noise amplification of a code's transfer function.
#pragma once

#include <span>

namespace fss {

struct KernelAnalysis {
  double k0 = 0.0;          // K(0) = dt * sum alpha_k
  double min_abs = 0.0;     // min |K(xi)| over xi in [-pi, pi]
  double min_abs_xi = 0.0;  // where it is reached (the non-negative one of a +/- pair)
  bool invertible = false;  // !transfer_vanishes(min_abs, scale, kInvertibilityTolerance)
};

// The one rule of where K vanishes (docs/method.md §4): |K| <= tolerance * s, with the code's
// scale s = dt * sum_k |alpha_k| (s >= sup |K|; s > 0 for any code with a nonzero gain).
// kZeroTolerance decides the zeros of K on a grid (the deconvolution's bins, M);
// kInvertibilityTolerance, at the minimum of |K| over the band, whether the code is invertible.
inline constexpr double kZeroTolerance = 1e-12;
inline constexpr double kInvertibilityTolerance = 1e-6;

// s = dt * sum_k |alpha_k|.
double transfer_scale(std::span<const double> gains, double dt);

// The level tolerance * scale at and below which |K| vanishes.
double transfer_zero_level(double scale, double tolerance = kZeroTolerance);

// |K| <= transfer_zero_level(scale, tolerance) (scale = transfer_scale).
bool transfer_vanishes(double abs_k, double scale, double tolerance = kZeroTolerance);

// K(0), the minimum of |K| over [-pi, pi] (a zero between grid points included) and whether
// the code is invertible.
KernelAnalysis analyze_kernel(std::span<const double> gains, double velocity, double dt);

// M = mean of 1 / |K|^2 over the n bins of an n-point DFT: the noise amplification of the
// inverse filter on that grid (docs/method.md §6). Infinite if K vanishes at a bin.
double mean_inverse_power(std::span<const double> gains, double velocity, double dt, int n);

}  // namespace fss
