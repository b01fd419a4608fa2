// The noise weights of the exact expected error (docs/method.md §6b).
//
// The restoration of one row is linear in its observed crop n_0 .. n_{Wa-1}
// (observation columns [h, h + Wa), restore.h): mirror extension to 2 Wa,
// inverse filter by K on the 2 Wa grid (bins where K vanishes left at 0), output
// column x = deconvolved column x + 2h. So restored column x of any row is
//   r_x = sum_j w_x(j) n_j,   w_x(j) = k[(x' - j) mod 2Wa] + k[(x' + j + 1) mod 2Wa],
// with x' = x + 2h and k = IDFT(1 / K) the inverse filter's impulse response
// (the second term is the mirror image of n_j, at column 2 Wa - 1 - j). The
// weights are the same for every row and channel.
//
// How the prediction uses them: the observation noise is independent from
// pixel to pixel and of mean 0, so for the RMSE window [first, end)
//   E[sum over the window of d^2] = (noise-free sum) + sum_j W(j) S(j),
//   W(j) = sum_{x in [first, end)} w_x(j)^2          (noise_energy_weights),
//   S(j) = sum over rows and channels of Var(n_j),
// the variance of observation column h + j at each pixel: numerical
// sum_k alpha_k^2 Var(PoissonSNR(e_k)), analog Var(PoissonSNR(e)), with
// Var(PoissonSNR(e)) = max(e, 0) / lambda2 (plus 1 / (12 lambda2^2) for the
// rounding of the normal branch, lambda >= 50), e the noise-free exposure of
// that pixel (slot k for the numerical mode). Then
//   predicted RMSE = sqrt(E[sum] / (rows * channels * (end - first))).
#pragma once

#include <span>
#include <vector>

#include "pipeline/restore.h"

namespace fss {

// W(j) for the observed-crop columns j in [0, Wa): the sum over output
// columns [window_first, window_end) of the squared weight of n_j in the
// restored value, for the restoration with `gains` at `restore_velocity`
// and `dt` on `geometry`. One inverse FFT of 1 / K on the 2 Wa grid
// (RowFFT), then O(Wa (window_end - window_first)). Throws a usage
// fss::Error for an empty or out-of-range window ([0, Wo) holds it), an
// empty code or a geometry without an observed crop.
std::vector<double> noise_energy_weights(const Geometry& geometry, std::span<const double> gains,
                                         double restore_velocity, double dt, int window_first,
                                         int window_end);

// The same for any restoration filter, from its impulse response k on the 2 Wa grid
// (filter_impulse_response, restoration_filter.h), in place of the inverse filter's.
std::vector<double> noise_energy_weights(const Geometry& geometry, std::vector<double> k,
                                         int window_first, int window_end);

}  // namespace fss
