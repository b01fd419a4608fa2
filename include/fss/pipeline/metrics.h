// Error measures (SPEC 5). Conventions: image.h. Images compared must have
// the same size; every function throws a usage fss::Error otherwise or when
// the column window is empty or out of range.
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

// sum over x in [first, end) of (a[x] - b[x])^2, in column order: the sum of
// one row in rmse(), shared with Simulate, which sums the rows of RMSE_0 as
// they stream by; rmse() adds the row sums in row order, so the same bits.
double row_squared_error(const double* a, const double* b, int first, int end);

// 10 log10(255^2 / rmse^2).
double psnr(double rmse_value);

// Midway equalization of two images of the same size, channel by channel:
// the i-th smallest value of each becomes the mean of the two i-th smallest
// values. Ties are broken by column-major pixel index (x * height + y), so
// the result is deterministic. Why column-major: the reference program sorts
// with an unstable sort, i.e. in effect a random tie order, and the integer
// ground truth is full of ties. Row-major order correlates with the
// restoration error, which runs along rows, and biases RMSE_CI (camera.png,
// raskar, noise-free: 1.00164 against the reference's 1.00512); column-major
// order gives 1.00532, inside the spread of random orders (about +/- 6e-4).
std::pair<Image, Image> midway_equalize(const Image& a, const Image& b);

// RMSE of the midway-equalized columns [first, end) of a and b. Ranks are
// sorted as 8-byte keys (the value's order-preserving bits, their low bits
// replaced by the column-major index, radix-sorted), so the scratch is 16
// bytes a pixel of one channel plus the sorter's buffer (half a byte a pixel,
// at least 2 MiB). Equal values are ranked by index exactly; values closer
// than 2^-(52 - index bits) relative (about 1e-10 for a 512 x 512 window) are
// ranked by index too, which moves their midway values by no more than that.
// With more than one thread and a window of at most kParallelSortPixels
// pixels, a and b are sorted at the same time (20 bytes a pixel and two
// buffers); the result is the same. A window above 2^32 pixels a channel is a
// usage error.
inline constexpr std::size_t kParallelSortPixels = std::size_t{1} << 22;
double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end, int threads = 1);
double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end,
                               int threads = 1);

// The range of a - b (a's column x + a_offset facing b's column x) and the
// affine map of the residual display: (d - min) / (max - min) * 255, every
// pixel including the first; dividing first makes both ends exact. A
// constant residual maps to 0.
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
