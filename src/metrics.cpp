#include "fss/metrics.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "fss/error.h"

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

// Sort keys that order (value, column-major index) pairs in 8 bytes: the
// value's order-preserving bit pattern with its low `index_bits` bits
// replaced by the index. Equal values are ordered by index exactly; values
// closer than about 2^(index_bits - 52) relative are ordered by index too,
// which moves their midway values by no more than that.
class RankKeys {
 public:
  explicit RankKeys(std::size_t n)
      : index_bits_(std::max(1, static_cast<int>(std::bit_width(n > 0 ? n - 1 : 0)))),
        index_mask_((std::uint64_t{1} << index_bits_) - 1) {}

  std::uint64_t key(double value, std::size_t index) const {
    if (value == 0.0) value = 0.0;  // -0 and +0 are equal values
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    // Order-preserving: flip all bits of negatives, the sign bit of positives.
    bits = (bits >> 63) ? ~bits : bits | (std::uint64_t{1} << 63);
    return (bits & ~index_mask_) | static_cast<std::uint64_t>(index);
  }
  std::size_t index(std::uint64_t key) const { return static_cast<std::size_t>(key & index_mask_); }

 private:
  int index_bits_;
  std::uint64_t index_mask_;
};

// Columns [first, end) of a channel of `image`, addressed by column-major
// index i = (x - first) * height + y.
struct Window {
  const Image* image;
  int channel;
  int first;
  int end;
  std::size_t size() const {
    return static_cast<std::size_t>(end - first) * static_cast<std::size_t>(image->height);
  }
  double operator[](std::size_t i) const {
    const auto h = static_cast<std::size_t>(image->height);
    return image->at(channel, static_cast<int>(i % h), first + static_cast<int>(i / h));
  }
};

// Least-significant-digit radix sort of 64-bit keys, 11-bit digits; a pass
// whose digit is the same for every key is skipped (the high bits of values
// in a narrow range). `buffer` is scratch of the same size.
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& buffer) {
  constexpr int kDigitBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  constexpr int kPasses = (64 + kDigitBits - 1) / kDigitBits;
  const std::size_t n = keys.size();
  if (n < 2) return;
  std::vector<std::size_t> counts(kPasses * kBuckets, 0);
  for (const std::uint64_t key : keys) {
    for (int p = 0; p < kPasses; ++p)
      ++counts[p * kBuckets + ((key >> (p * kDigitBits)) & (kBuckets - 1))];
  }
  buffer.resize(n);
  for (int p = 0; p < kPasses; ++p) {
    std::size_t* count = counts.data() + p * kBuckets;
    const int shift = p * kDigitBits;
    if (count[(keys[0] >> shift) & (kBuckets - 1)] == n) continue;  // one digit value: no-op
    std::size_t start = 0;
    for (std::size_t d = 0; d < kBuckets; ++d) {
      const std::size_t c = count[d];
      count[d] = start;
      start += c;
    }
    for (const std::uint64_t key : keys) buffer[count[(key >> shift) & (kBuckets - 1)]++] = key;
    keys.swap(buffer);
  }
}

std::vector<std::uint64_t> sorted_keys(const Window& w, const RankKeys& keys,
                                       std::vector<std::uint64_t>& buffer) {
  std::vector<std::uint64_t> sorted(w.size());
  std::size_t i = 0;
  for (int x = w.first; x < w.end; ++x) {
    for (int y = 0; y < w.image->height; ++y, ++i) {
      sorted[i] = keys.key(w.image->at(w.channel, y, x), i);
    }
  }
  radix_sort(sorted, buffer);
  return sorted;
}

// The ranks of two windows of equal size: keys sorted, so that rank i pairs
// a's pixel keys.index(a_sorted[i]) with b's pixel keys.index(b_sorted[i]).
struct MidwayRanks {
  RankKeys keys;
  std::vector<std::uint64_t> a_sorted;
  std::vector<std::uint64_t> b_sorted;
  MidwayRanks(const Window& a, const Window& b) : keys(a.size()) {
    std::vector<std::uint64_t> buffer;
    a_sorted = sorted_keys(a, keys, buffer);
    b_sorted = sorted_keys(b, keys, buffer);
  }
};

}  // namespace

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
      const double* pa = a.row(c, y) + a_offset;
      const double* pb = b.row(c, y);
      double row_sum = 0.0;
      for (int x = first; x < end; ++x) {
        const double d = pa[x] - pb[x];
        row_sum += d * d;
      }
      sum += row_sum;
    }
  }
  const double count = static_cast<double>(end - first) * b.height * b.channels;
  return std::sqrt(sum / count);
}

double psnr(double rmse_value) {
  // 10 log10(255^2 / RMSE^2)
  return 10.0 * std::log10(255.0 * 255.0 / (rmse_value * rmse_value));
}

std::pair<Image, Image> midway_equalize(const Image& a, const Image& b) {
  require_same_size(a, b);
  Image ea(a.width, a.height, a.channels);
  Image eb(b.width, b.height, b.channels);
  const auto h = static_cast<std::size_t>(a.height);
  for (int c = 0; c < a.channels; ++c) {
    const Window wa{&a, c, 0, a.width};
    const Window wb{&b, c, 0, b.width};
    const MidwayRanks ranks(wa, wb);
    for (std::size_t i = 0; i < ranks.a_sorted.size(); ++i) {
      const std::size_t ia = ranks.keys.index(ranks.a_sorted[i]);
      const std::size_t ib = ranks.keys.index(ranks.b_sorted[i]);
      const double mid = 0.5 * (wa[ia] + wb[ib]);  // the i-th smallest of each becomes their mean
      ea.at(c, static_cast<int>(ia % h), static_cast<int>(ia / h)) = mid;
      eb.at(c, static_cast<int>(ib % h), static_cast<int>(ib / h)) = mid;
    }
  }
  return {std::move(ea), std::move(eb)};
}

double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end) {
  require_same_size(a, b);
  return rmse_contrast_invariant(a, 0, b, first, end);
}

double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end) {
  require_aligned(a, a_offset, b);
  require_window(b, first, end);
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    const Window wa{&a, c, first + a_offset, end + a_offset};
    const Window wb{&b, c, first, end};
    MidwayRanks ranks(wa, wb);
    const std::size_t n = ranks.a_sorted.size();
    // rank_of_a[p]: the rank of a's pixel p. The midway value of rank i,
    // mean of the two i-th smallest values, then replaces a_sorted[i].
    std::vector<std::uint32_t> rank_of_a(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t ia = ranks.keys.index(ranks.a_sorted[i]);
      rank_of_a[ia] = static_cast<std::uint32_t>(i);
      const double mid = 0.5 * (wa[ia] + wb[ranks.keys.index(ranks.b_sorted[i])]);
      std::memcpy(&ranks.a_sorted[i], &mid, sizeof mid);
    }
    auto mid_of_rank = [&](std::size_t i) {
      double mid;
      std::memcpy(&mid, &ranks.a_sorted[i], sizeof mid);
      return mid;
    };
    // At b's pixel of rank i: equalized b is mid(i), equalized a is mid(rank of a there).
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t pixel = ranks.keys.index(ranks.b_sorted[i]);
      const double d = mid_of_rank(rank_of_a[pixel]) - mid_of_rank(i);
      sum += d * d;
    }
  }
  const double count = static_cast<double>(end - first) * b.height * b.channels;
  return std::sqrt(sum / count);
}

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
