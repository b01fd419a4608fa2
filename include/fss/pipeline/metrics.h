// Error measures (docs/method.md §5). Conventions: image.h. Images compared must have
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

// 10 log10(255^2 / rmse^2): +inf for rmse = 0 (a perfect restoration), and
// finite for any other rmse, however small or large.
double psnr(double rmse_value);

// Midway equalization (docs/method.md §5) of two images of the same size,
// channel by channel: with a and b sorted, mid_i = (a_(i) + b_(i)) / 2 is
// the value rank i of both takes. Which rank a pixel holds inside a group of
// equal values is arbitrary, so each pixel gets the expectation of its
// equalized value over all orders of its group: B_G, the mean of mid_i over
// the group's ranks. Without ties this is plain midway equalization. With
// ties, rmse_contrast_invariant is not the RMSE of these two images: it is
// the expectation of the squared difference, which also counts the spread
// of mid_i inside the groups.
std::pair<Image, Image> midway_equalize(const Image& a, const Image& b);

// RMSE_CI (docs/method.md §5): the RMSE of the midway-equalized columns
// [first, end) of a and b, channels equalized separately and pooled, taken
// as the expectation over independent uniform orders of each group of equal
// values of a and of b (the ground truth is 8-bit and full of ties; any
// fixed order of a group, such as by pixel index, biases the result and
// depends on the pixel layout). For a pixel p in a's group G (ranks I_G) and
// b's group H (ranks J_H), with B and A the means of mid_i and mid_i^2 over a
// group's ranks, the two orders being independent:
//   E[(a'_p - b'_p)^2] = A_G - 2 B_G B_H + A_H
//                      = (A_G - B_G^2) + (A_H - B_H^2) + (B_G - B_H)^2,
//   RMSE_CI = sqrt(sum over the pixels of all channels / count).
// It is summed as in the second form (no cancellation) and in an order fixed
// by the values alone, so it is deterministic and bit-identical for any
// arrangement of the pixels (a mirrored pair of images gives the same bits).
// Ranks come from a bucket sort of 16-byte records, one a pixel of the
// channel: b's value (its order-preserving bits: exact) and a's group at
// that pixel. A ground truth on a lattice (integers in [0, 65535], or
// k / 257: 8- and 16-bit images) is grouped by a histogram of its levels,
// any other by sorting records of a's and b's values first. The records are
// scattered, the pixels read in order, into buckets of about 8192 linear in
// b's value between two quantiles of a sample (one bucket more below and
// one above); each bucket is sorted in cache, by value and a's group, and
// swept at once for its midway values and a's group sums; one pass over the
// ranks then takes the sums. The scratch is 16 bytes and at most 1 bit a
// pixel of one channel (the records, a's group starts), plus 8 bytes per
// distinct value of a's window (2 KiB for 8-bit images), plus about 5 MiB
// of buffers (level counts, the sorters' buffers, b's tied runs). With more
// than one thread, and a window of at least kParallelRmseCiPixels pixels a
// channel, two threads count, scatter and sort (each of a's groups summed
// by one of them) and take the sums (each sum by one of them): the result
// is the same. A window above 2^32 pixels a channel is a usage error.
// (Measured with both cores free: 2^18 pixels took 4.8 ms on one thread,
// 5.5 on two; 2^19, 9.4 and 8.8; camera.png's 129024, 2.35 and 2.98.)
inline constexpr std::size_t kParallelRmseCiPixels = std::size_t{1} << 19;
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
