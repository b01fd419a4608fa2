// Error measures (docs/method.md §5). Every function throws a usage fss::Error for images of
// different sizes or an empty or out-of-range column window. Conventions: fss/fss.h.
#pragma once

#include <cstddef>
#include <utility>

#include "fss/core/image.h"

namespace fss {

// sqrt(mean (a - b)^2) over columns [first, end), all rows, channels pooled.
double rmse(const Image& a, const Image& b, int first, int end);
// Same with a wider `a` whose column x + a_offset faces b's column x (a can
// be the input and b the Wo-wide restoration: no crop is copied).
double rmse(const Image& a, int a_offset, const Image& b, int first, int end);

// sum over x in [first, end) of (a[x] - b[x])^2, in column order: one row's sum in rmse(), which
// adds them in row order; a caller that streams rows gets rmse()'s bits the same way.
double row_squared_error(const double* a, const double* b, int first, int end);

// 10 log10(255^2 / rmse^2): +inf for rmse = 0 (a perfect restoration), and
// finite for any other rmse, however small or large.
double psnr(double rmse_value);

// Midway equalization (docs/method.md §5) of two images of the same size, channel by channel.
// A pixel of a group of equal values gets the mean of the midway values over the group's ranks
// (its expectation over the orders of the group). With ties, rmse_contrast_invariant is not the
// RMSE of these two images: it also counts the spread of the midway values inside the groups.
std::pair<Image, Image> midway_equalize(const Image& a, const Image& b);

// RMSE_CI (docs/method.md §5): the RMSE of the midway-equalized columns [first, end) of a and b
// (a_offset as for rmse), channels equalized separately and pooled, taken as the expectation over
// independent uniform orders of each group of equal values. Deterministic: the same bits for any
// arrangement of the pixels and any `threads`; a window of kParallelRmseCiPixels pixels a channel
// or more is worked on by two threads when `threads` allows. Scratch: about 16 bytes a pixel of
// one channel's window plus about 5 MiB. A window above 2^32 pixels a channel is a usage error.
inline constexpr std::size_t kParallelRmseCiPixels = std::size_t{1} << 19;
double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end, int threads = 1);
double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end,
                               int threads = 1);

// The range of a - b (a's column x + a_offset facing b's column x) and the affine map of the
// residual display, (d - min) / (max - min) * 255, exact at both ends; a constant residual maps
// to 0.
struct ResidualRange {
  double min = 0.0;
  double max = 0.0;
  double stretch(double d) const { return max > min ? (d - min) / (max - min) * 255.0 : 0.0; }
};
ResidualRange residual_range(const Image& a, int a_offset, const Image& b);

// a - b mapped affinely so that its minimum goes to 0 and its maximum to 255,
// all channels jointly (all 0 when a - b is constant).
Image residual_display(const Image& a, const Image& b);

}  // namespace fss
