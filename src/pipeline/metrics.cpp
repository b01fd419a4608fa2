#include "fss/pipeline/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/parallel.h"
#include "core/scaled_math.h"
#include "fss/core/error.h"
#include "pipeline/expected_midway.h"
#include "pipeline/record_sort.h"

namespace fss {

namespace {

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
         std::to_string(image.channels);
}

void require_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    throw_usage_error("images of different sizes cannot be compared: " + size_text(a) + " and " +
                      size_text(b));
  }
}

// a's columns [offset, offset + b.width) face b's columns.
void require_aligned(const Image& a, int a_offset, const Image& b) {
  if (a.height != b.height || a.channels != b.channels || a_offset < 0 ||
      a_offset + b.width > a.width) {
    throw_usage_error("image " + size_text(b) + " cannot face columns [" +
                      std::to_string(a_offset) + ", " + std::to_string(a_offset + b.width) +
                      ") of image " + size_text(a));
  }
}

void require_window(const Image& image, int first, int end) {
  if (first < 0 || end > image.width || first >= end) {
    throw_usage_error("column window [" + std::to_string(first) + ", " + std::to_string(end) +
                      ") is empty or outside an image of width " + std::to_string(image.width));
  }
}

// Ranks are counted in 64 bits, but a window of more than 2^32 pixels a
// channel (34 GB of doubles) is refused, as it always was.
constexpr std::size_t kMaxRankedPixels = std::size_t{1} << 32;

// Columns [first, end) of channel c.
midway::ChannelWindow channel_window(const Image& image, int c, int first, int end) {
  midway::ChannelWindow w;
  w.first = image.row(c, 0) + first;
  w.stride = static_cast<std::size_t>(image.width);
  w.width = static_cast<std::uint32_t>(end - first);
  w.height = static_cast<std::uint32_t>(image.height);
  return w;
}

// The group means of the midway values of a sorted sample: element i is
// B of the group of equal values holding rank i (bits compared, -0 = +0).
std::vector<double> group_means(const std::vector<double>& sorted, const std::vector<double>& mid) {
  std::vector<double> means(sorted.size());
  std::size_t begin = 0;
  while (begin < sorted.size()) {
    std::size_t end = begin + 1;
    while (end < sorted.size() &&
           midway::ordered_bits(sorted[end]) == midway::ordered_bits(sorted[begin])) {
      ++end;
    }
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) sum += mid[i];
    std::fill(means.begin() + static_cast<std::ptrdiff_t>(begin),
              means.begin() + static_cast<std::ptrdiff_t>(end),
              sum / static_cast<double>(end - begin));
    begin = end;
  }
  return means;
}

bool ordered_less(double x, double y) { return midway::ordered_bits(x) < midway::ordered_bits(y); }

}  // namespace

double row_squared_error(const double* a, const double* b, int first, int end) {
  double sum = 0.0;
  for (int x = first; x < end; ++x) {
    const double d = a[x] - b[x];
    sum += d * d;
  }
  return sum;
}

double rmse(const Image& a, const Image& b, int first, int end) {
  require_same_size(a, b);
  return rmse(a, 0, b, first, end);
}

double rmse(const Image& a, int a_offset, const Image& b, int first, int end) {
  require_aligned(a, a_offset, b);
  require_window(b, first, end);
  // Summed row by row, then over rows in order: a row-streamed computation
  // that keeps one sum per row gets the same bits.
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    for (int y = 0; y < b.height; ++y) {
      sum += row_squared_error(a.row(c, y) + a_offset, b.row(c, y), first, end);
    }
  }
  const double count = static_cast<double>(end - first) * b.height * b.channels;
  return std::sqrt(sum / count);
}

double psnr(double rmse_value) {
  // 10 log10(255^2 / RMSE^2); +inf for RMSE = 0
  const double square = rmse_value * rmse_value;
  if (detail::is_normal_positive(square) || rmse_value == 0.0 || !std::isfinite(rmse_value)) {
    return 10.0 * std::log10(255.0 * 255.0 / square);
  }
  // RMSE^2 under- or overflows: 20 (log10 255 - log10 RMSE)
  return 20.0 * (std::log10(255.0) - std::log10(rmse_value));
}

// With a and b sorted, mid_i = (a_(i) + b_(i)) / 2 is the value rank i of both takes. Which rank
// a pixel holds inside a group of equal values is arbitrary, so each pixel gets B_G, the mean of
// mid_i over its group's ranks; without ties this is plain midway equalization.
std::pair<Image, Image> midway_equalize(const Image& a, const Image& b) {
  require_same_size(a, b);
  Image ea(a.width, a.height, a.channels);
  Image eb(b.width, b.height, b.channels);
  const std::size_t n = a.plane_size();
  for (int c = 0; c < a.channels; ++c) {
    const auto offset = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(c) * n);
    std::vector<double> sa(a.data.begin() + offset, a.data.begin() + offset + n);
    std::vector<double> sb(b.data.begin() + offset, b.data.begin() + offset + n);
    std::sort(sa.begin(), sa.end(), ordered_less);
    std::sort(sb.begin(), sb.end(), ordered_less);
    std::vector<double> mid(n);
    for (std::size_t i = 0; i < n; ++i) mid[i] = 0.5 * (sa[i] + sb[i]);
    const std::vector<double> a_means = group_means(sa, mid);
    const std::vector<double> b_means = group_means(sb, mid);
    for (std::size_t p = 0; p < n; ++p) {
      const auto q = static_cast<std::size_t>(offset) + p;
      ea.data[q] = a_means[static_cast<std::size_t>(
          std::lower_bound(sa.begin(), sa.end(), a.data[q], ordered_less) - sa.begin())];
      eb.data[q] = b_means[static_cast<std::size_t>(
          std::lower_bound(sb.begin(), sb.end(), b.data[q], ordered_less) - sb.begin())];
    }
  }
  return {std::move(ea), std::move(eb)};
}

double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end, int threads) {
  require_same_size(a, b);
  return rmse_contrast_invariant(a, 0, b, first, end, threads);
}

// The expectation (docs/method.md §5): for a pixel p in a's group G (ranks I_G) and b's group H
// (ranks J_H), with B and A the means of mid_i and mid_i^2 over a group's ranks, the two orders
// being independent,
//   E[(a'_p - b'_p)^2] = A_G - 2 B_G B_H + A_H = (A_G - B_G^2) + (A_H - B_H^2) + (B_G - B_H)^2,
// summed as in the second form (no cancellation) and in an order fixed by the values alone, so
// that any arrangement of the pixels (a mirrored pair of images) gives the same bits. Ranks come
// from a bucket sort of 16-byte records, one a pixel of the channel: b's value (its
// order-preserving bits: exact) and a's group at that pixel. A ground truth on a lattice
// (integers in [0, 65535], or k / 257: 8- and 16-bit images) is grouped by a histogram of its
// levels, any other by sorting records of a's and b's values first. The records are scattered,
// the pixels read in order, into buckets of about 8192 linear in b's value between two quantiles
// of a sample (one bucket more below and one above); each bucket is sorted in cache, by value and
// a's group, and swept at once for its midway values and a's group sums; one pass over the ranks
// then takes the sums. The scratch is 16 bytes and at most 1 bit a pixel of one channel (the
// records, a's group starts), plus 8 bytes per distinct value of a's window, plus about 5 MiB of
// buffers (level counts, the sorters' buffers, b's tied runs). With two workers, two threads
// count, scatter and sort (each of a's groups summed by one of them) and take the sums (each sum
// by one of them): the result is the same.
double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end,
                               int threads) {
  require_aligned(a, a_offset, b);
  require_window(b, first, end);
  const std::size_t window = static_cast<std::size_t>(end - first) * b.height;
  if (window > kMaxRankedPixels) {
    throw_usage_error("a window of " + std::to_string(window) +
                      " pixels a channel is too large to rank: at most 2^32 are supported");
  }
  const int workers = window >= kParallelRmseCiPixels && resolve_thread_count(threads) > 1 ? 2 : 1;
  // The channels one after the other, in one scratch of 16 bytes a pixel
  // (midway::Record), left uninitialized: its pages are first touched by
  // the first channel's records.
  midway::RecordBuffer records(window);
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    sum += midway::expected_midway_sum(channel_window(a, c, first + a_offset, end + a_offset),
                                       channel_window(b, c, first, end), records.data(), workers);
  }
  const double count = static_cast<double>(end - first) * b.height * b.channels;
  return std::sqrt(sum / count);
}

// Every pixel counts, the first included; ResidualRange::stretch divides before it multiplies,
// which makes both ends exact.
ResidualRange residual_range(const Image& a, int a_offset, const Image& b) {
  require_aligned(a, a_offset, b);
  ResidualRange range{std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity()};
  for (int c = 0; c < b.channels; ++c) {
    for (int y = 0; y < b.height; ++y) {
      const double* pa = a.row(c, y) + a_offset;
      const double* pb = b.row(c, y);
      for (int x = 0; x < b.width; ++x) {
        const double d = pa[x] - pb[x];
        range.min = std::min(range.min, d);
        range.max = std::max(range.max, d);
      }
    }
  }
  return range;
}

Image residual_display(const Image& a, const Image& b) {
  require_same_size(a, b);
  const ResidualRange range = residual_range(a, 0, b);
  Image d(a.width, a.height, a.channels);
  for (std::size_t i = 0; i < a.data.size(); ++i) d.data[i] = range.stretch(a.data[i] - b.data[i]);
  return d;
}

}  // namespace fss
