// The structural similarity (SSIM) of a restoration to its ground truth, over the RMSE window
// (docs/method.md §5). Internal to the library.
#pragma once

#include <optional>

#include "fss/core/image.h"

namespace fss {

// The Gaussian window of SSIM: standard deviation kSsimSigma, truncated at kSsimRadius pixels
// (11 x 11 weights), separable.
inline constexpr double kSsimSigma = 1.5;
inline constexpr int kSsimRadius = 5;

// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) of x = `restored` to the ground truth g = columns
// [offset, offset + restored.width) of `input` (same rows and channels), with the Gaussian window
// above, C1 = (0.01 * 255)^2, C2 = (0.03 * 255)^2 and population (co)variances:
//   SSIM(p) = (2 mu_g mu_x + C1)(2 s_gx + C2) / ((mu_g^2 + mu_x^2 + C1)(s_g^2 + s_x^2 + C2)),
//   mu_g = sum w g, s_g^2 = sum w g^2 - mu_g^2, s_gx = sum w g x - mu_g mu_x (likewise for x).
// The value is the mean of SSIM(p) over output columns [first, end) and rows
// [kSsimRadius, height - kSsimRadius), each pixel taken from its real 11 x 11 neighbours (no
// padding); with several channels, the mean over the channels of each channel's mean. This is
// scikit-image's structural_similarity(g, x, gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=255) on columns [first - 5, end + 5).
// nullopt when no pixel is left: first < 5, end + 5 > restored.width, fewer than 11 rows or no
// channel. Throws a usage fss::Error, as rmse() does, when the images do not face each other or
// the window [first, end) is empty or outside `restored`. The result has the same bits for any
// `threads` (0: all hardware threads).
std::optional<double> structural_similarity(const Image& input, int offset, const Image& restored,
                                            int first, int end, int threads = 1);

}  // namespace fss
