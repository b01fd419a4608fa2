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

// The one rule that decides where K vanishes (docs/method.md §4), relative to
// the code's scale s = dt * sum_k |alpha_k| (sup |K| <= s; s > 0 for any code
// with a nonzero gain, whatever sum_k alpha_k is):
//   |K| <= tolerance * s.
// kZeroTolerance decides the zeros of K on a grid (the deconvolution's bins,
// M): a zero of sinc_h or of the gains' polynomial computed in double
// precision comes out as round-off of about 1e-16 s, not as 0.
// kInvertibilityTolerance decides, at the minimum of |K| over the band,
// whether the code is invertible at all.
inline constexpr double kZeroTolerance = 1e-12;
inline constexpr double kInvertibilityTolerance = 1e-6;

// s = dt * sum_k |alpha_k|.
double transfer_scale(std::span<const double> gains, double dt);

// The level tolerance * scale at and below which |K| vanishes.
double transfer_zero_level(double scale, double tolerance = kZeroTolerance);

// |K| <= transfer_zero_level(scale, tolerance) (scale = transfer_scale).
bool transfer_vanishes(double abs_k, double scale, double tolerance = kZeroTolerance);

// Scans |K| densely over [-pi, pi] and refines every local minimum by golden
// section search, so a zero between samples is found.
KernelAnalysis analyze_kernel(std::span<const double> gains, double velocity, double dt);

// M = mean over the N bins of an N-point DFT of 1 / |K(xi)|^2: the noise
// amplification of the inverse filter on that grid. Infinite if K vanishes at
// a bin (transfer_vanishes).
double mean_inverse_power(std::span<const double> gains, double velocity, double dt, int n);

}  // namespace fss
