#include "fss/pipeline/metrics.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <limits>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/parallel.h"

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

// Radix sort of 64-bit keys whose scratch is bounded by `max_scratch` keys
// rather than n. Digits are 11 bits wide and only the bits below the highest
// one in which the keys differ count. A range of at most max_scratch keys is
// sorted least-significant digit first through a buffer of its size; a
// longer one is split in place on its most significant digit ("American
// flag" permutation: each misplaced key cycled to the next free slot of its
// digit), then each part is sorted the same way.
// Keys of scratch for sorting n keys: a sixteenth of them (half a byte a
// pixel), and at least 256 Ki keys (2 MiB), so that small windows are
// sorted by buffered passes alone (faster than splitting them).
std::size_t sort_scratch_keys(std::size_t n) { return std::max<std::size_t>(n / 16, 1 << 18); }

class KeySorter {
 public:
  // The buffer is reserved once for the largest range it can serve, so it
  // never reallocates (no moment with two copies).
  KeySorter(std::size_t n, std::size_t max_scratch)
      : max_scratch_(std::max<std::size_t>(max_scratch, 1)) {
    buffer_.reserve(std::min(n, max_scratch_));
  }

  void sort(std::uint64_t* keys, std::size_t n) {
    if (n < kSmall) {
      std::sort(keys, keys + n);
      return;
    }
    const auto [low, high] = std::minmax_element(keys, keys + n);
    if (*low == *high) return;
    const int top_bit = 63 - std::countl_zero(*low ^ *high);  // highest differing bit
    if (n <= max_scratch_) {
      sort_lsd(keys, n, top_bit);
    } else {
      split_msd(keys, n, std::max(0, top_bit - kDigitBits + 1));
    }
  }

 private:
  static constexpr int kDigitBits = 11;
  static constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  // Below this, std::sort beats LSD passes that each walk 2048 counters.
  static constexpr std::size_t kSmall = 1024;

  void sort_lsd(std::uint64_t* keys, std::size_t n, int top_bit) {
    const int passes = top_bit / kDigitBits + 1;
    // Every pass's histogram in one read of the keys.
    std::vector<std::size_t> counts(static_cast<std::size_t>(passes) * kBuckets, 0);
    for (std::size_t i = 0; i < n; ++i) {
      for (int p = 0; p < passes; ++p) {
        ++counts[p * kBuckets + ((keys[i] >> (p * kDigitBits)) & (kBuckets - 1))];
      }
    }
    buffer_.resize(n);
    std::uint64_t* from = keys;
    std::uint64_t* to = buffer_.data();
    for (int p = 0; p < passes; ++p) {
      std::size_t* count = counts.data() + p * kBuckets;
      const int shift = p * kDigitBits;
      if (count[(from[0] >> shift) & (kBuckets - 1)] == n) continue;  // one digit value
      std::size_t start = 0;
      for (std::size_t d = 0; d < kBuckets; ++d) start += std::exchange(count[d], start);
      for (std::size_t i = 0; i < n; ++i)
        to[count[(from[i] >> shift) & (kBuckets - 1)]++] = from[i];
      std::swap(from, to);
    }
    if (from != keys) std::copy(from, from + n, keys);
  }

  void split_msd(std::uint64_t* keys, std::size_t n, int shift) {
    std::vector<std::size_t> next(kBuckets, 0);  // where the next key of each digit goes
    std::vector<std::size_t> stop(kBuckets, 0);  // one past each digit's range
    for (std::size_t i = 0; i < n; ++i) ++stop[(keys[i] >> shift) & (kBuckets - 1)];
    std::size_t start = 0;
    for (std::size_t d = 0; d < kBuckets; ++d) {
      next[d] = start;
      start += stop[d];
      stop[d] = start;
    }
    for (std::size_t d = 0; d < kBuckets; ++d) {
      while (next[d] < stop[d]) {
        std::uint64_t key = keys[next[d]];
        std::size_t digit = (key >> shift) & (kBuckets - 1);
        while (digit != d) {
          std::swap(key, keys[next[digit]++]);
          digit = (key >> shift) & (kBuckets - 1);
        }
        keys[next[d]++] = key;
      }
    }
    std::size_t begin = 0;
    for (std::size_t d = 0; d < kBuckets; ++d) {
      sort(keys + begin, stop[d] - begin);  // the part's own highest differing bit is lower
      begin = stop[d];
    }
  }

  std::size_t max_scratch_;
  std::vector<std::uint64_t> buffer_;
};

// The rank keys of a window, sorted: key i holds the column-major index of
// the window's i-th smallest pixel. The image is read row by row (the keys
// carry their index, so the order they are made in does not matter).
std::vector<std::uint64_t> sorted_keys(const Window& w, const RankKeys& keys) {
  std::vector<std::uint64_t> sorted(w.size());
  const auto h = static_cast<std::size_t>(w.image->height);
  std::size_t k = 0;
  for (int y = 0; y < w.image->height; ++y) {
    const double* row = w.image->row(w.channel, y);
    for (int x = w.first; x < w.end; ++x) {
      sorted[k++] = keys.key(row[x], static_cast<std::size_t>(x - w.first) * h + y);
    }
  }
  KeySorter(sorted.size(), sort_scratch_keys(sorted.size())).sort(sorted.data(), sorted.size());
  return sorted;
}

// Ranks and pixel indices are 32-bit.
constexpr std::size_t kMaxRankedPixels = std::size_t{1} << 32;

// Midway equalization of two windows of equal size by ranks: the pixels of
// rank i of a and of b both become mid(i), the mean of the two i-th smallest
// values. Kept: the rank of each of a's pixels, the pixel of each rank of b
// (column-major indices) and the midway values; scratch at its peak is 16
// bytes a pixel (a's ranks and pixels, b's sorted 8-byte keys) plus the
// sorter's buffer (sort_scratch_keys).
class MidwayRanks {
 public:
  // With `in_parallel`, b's keys are sorted on another thread while a's are
  // (20 bytes a pixel at the peak and two sorter buffers; the same result).
  MidwayRanks(const Window& a, const Window& b, bool in_parallel = false) {
    const std::size_t n = a.size();
    if (n > kMaxRankedPixels) {
      throw_usage_error("a window of " + std::to_string(n) +
                        " pixels a channel is too large to rank: at most 2^32 are supported");
    }
    const RankKeys keys(n);
    std::vector<std::uint32_t> pixel;  // a's pixel of each rank, then b's
    std::future<std::vector<std::uint64_t>> b_sorted;
    if (in_parallel) {
      try {
        b_sorted = std::async(std::launch::async, [&] { return sorted_keys(b, keys); });
      } catch (const std::system_error&) {
        // no thread: sort b after a
      }
    }
    {
      const std::vector<std::uint64_t> a_sorted = sorted_keys(a, keys);
      pixel.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        pixel[i] = static_cast<std::uint32_t>(keys.index(a_sorted[i]));
      }
    }
    a_rank.resize(n);
    for (std::size_t i = 0; i < n; ++i) a_rank[pixel[i]] = static_cast<std::uint32_t>(i);
    mid_bits_ = b_sorted.valid() ? b_sorted.get() : sorted_keys(b, keys);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t b_pixel = keys.index(mid_bits_[i]);
      const double mid = 0.5 * (a[pixel[i]] + b[b_pixel]);  // the two i-th smallest: their mean
      pixel[i] = static_cast<std::uint32_t>(b_pixel);
      std::memcpy(&mid_bits_[i], &mid, sizeof mid);
    }
    b_pixel = std::move(pixel);
  }
  double mid(std::size_t i) const {
    double value;
    std::memcpy(&value, &mid_bits_[i], sizeof value);
    return value;
  }
  std::size_t size() const { return mid_bits_.size(); }

  std::vector<std::uint32_t> a_rank;   // by a's pixel
  std::vector<std::uint32_t> b_pixel;  // by rank

 private:
  std::vector<std::uint64_t> mid_bits_;  // by rank
};

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
  // 10 log10(255^2 / RMSE^2)
  return 10.0 * std::log10(255.0 * 255.0 / (rmse_value * rmse_value));
}

std::pair<Image, Image> midway_equalize(const Image& a, const Image& b) {
  require_same_size(a, b);
  Image ea(a.width, a.height, a.channels);
  Image eb(b.width, b.height, b.channels);
  const auto h = static_cast<std::size_t>(a.height);
  auto at = [h](Image& image, int c, std::size_t pixel) -> double& {
    return image.at(c, static_cast<int>(pixel % h), static_cast<int>(pixel / h));
  };
  for (int c = 0; c < a.channels; ++c) {
    const MidwayRanks ranks(Window{&a, c, 0, a.width}, Window{&b, c, 0, b.width});
    for (std::size_t p = 0; p < ranks.size(); ++p) at(ea, c, p) = ranks.mid(ranks.a_rank[p]);
    for (std::size_t i = 0; i < ranks.size(); ++i) at(eb, c, ranks.b_pixel[i]) = ranks.mid(i);
  }
  return {std::move(ea), std::move(eb)};
}

double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end, int threads) {
  require_same_size(a, b);
  return rmse_contrast_invariant(a, 0, b, first, end, threads);
}

double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end,
                               int threads) {
  require_aligned(a, a_offset, b);
  require_window(b, first, end);
  const std::size_t window = static_cast<std::size_t>(end - first) * b.height;
  const bool in_parallel = resolve_thread_count(threads) > 1 && window <= kParallelSortPixels;
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    const MidwayRanks ranks(Window{&a, c, first + a_offset, end + a_offset},
                            Window{&b, c, first, end}, in_parallel);
    // At b's pixel of rank i: equalized b is mid(i), equalized a is mid(rank of a there).
    for (std::size_t i = 0; i < ranks.size(); ++i) {
      const double d = ranks.mid(ranks.a_rank[ranks.b_pixel[i]]) - ranks.mid(i);
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
