#include "fss/pipeline/metrics.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <limits>
#include <numeric>
#include <optional>
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

// The order-preserving bit pattern of a value: comparing two patterns as
// unsigned integers compares the values (-0 and +0 are the same value).
std::uint64_t ordered_bits(double value) {
  if (value == 0.0) value = 0.0;
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  // Flip all bits of negatives, the sign bit of positives.
  return (bits >> 63) ? ~bits : bits | (std::uint64_t{1} << 63);
}

// Sort keys that carry a pixel in 8 bytes: a value's ordered bits with their
// low `index_bits` bits replaced by the pixel index. Sorting the keys sorts
// the values by their bits above the index (their "value part") and tells
// the pixel of each rank. The index only carries the pixel: no order that
// matters is decided by it (order_runs puts each run of equal value parts
// in the exact order of the values).
class PixelKeys {
 public:
  explicit PixelKeys(std::size_t n)
      : index_bits_(std::max(1, static_cast<int>(std::bit_width(n > 0 ? n - 1 : 0)))),
        index_mask_((std::uint64_t{1} << index_bits_) - 1) {}

  std::uint64_t key(std::uint64_t bits, std::uint32_t pixel) const {
    return (bits & ~index_mask_) | pixel;
  }
  std::uint32_t pixel(std::uint64_t key) const {
    return static_cast<std::uint32_t>(key & index_mask_);
  }
  std::uint64_t value_part(std::uint64_t key) const { return key & ~index_mask_; }
  // True when the value part of `bits` is all of it (its dropped bits are 0).
  bool keeps_all(std::uint64_t bits) const { return (bits & index_mask_) == 0; }
  int index_bits() const { return index_bits_; }

 private:
  int index_bits_;
  std::uint64_t index_mask_;
};

// Columns [first, end) of a channel of `image`, pixel p = y * width +
// (x - first). Row y = p / width without a division instruction: the
// rounded quotient in doubles (p < 2^32, so it is off by at most one),
// corrected.
class Window {
 public:
  Window(const Image* image, int channel, int first, int end)
      : image_(image),
        channel_(channel),
        first_(first),
        width_(static_cast<std::uint32_t>(end - first)),
        inverse_width_(1.0 / static_cast<double>(end - first)) {}
  std::size_t size() const {
    return std::size_t{width_} * static_cast<std::size_t>(image_->height);
  }
  std::uint32_t width() const { return width_; }
  const double* row(int y) const { return image_->row(channel_, y) + first_; }
  double operator[](std::uint32_t p) const { return *address(p); }
  const double* address(std::uint32_t p) const {
    auto y = static_cast<std::uint32_t>(static_cast<double>(p) * inverse_width_);
    if (y * std::uint64_t{width_} > p) --y;
    if ((y + 1) * std::uint64_t{width_} <= p) ++y;
    return row(static_cast<int>(y)) + (p - y * width_);
  }

 private:
  const Image* image_;
  int channel_;
  int first_;
  std::uint32_t width_;
  double inverse_width_;
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
  // Only bits from `low_bit` up are sorted on: the bits below (a pixel
  // index, PixelKeys) are left in any order.
  KeySorter(std::size_t n, std::size_t max_scratch, int low_bit)
      : max_scratch_(std::max<std::size_t>(max_scratch, 1)), low_bit_(low_bit) {
    buffer_.reserve(std::min(n, max_scratch_));
  }

  // As sort(), but when the keys need an in-place split, the parts of the
  // first split are sorted on two threads (the second with its own buffer),
  // largest parts first. Each part is sorted as sort() would sort it, so the
  // result is the same.
  void sort_on_two_threads(std::uint64_t* keys, std::size_t n) {
    if (n <= max_scratch_ || n < kSmall) {
      sort(keys, n);
      return;
    }
    const auto [low, high] = std::minmax_element(keys, keys + n);
    if ((*low ^ *high) >> low_bit_ == 0) return;
    const int top_bit = 63 - std::countl_zero(*low ^ *high);
    const std::vector<std::size_t> stop =
        partition(keys, n, std::max(low_bit_, top_bit - kDigitBits + 1));
    std::vector<std::size_t> parts(kBuckets);
    std::iota(parts.begin(), parts.end(), std::size_t{0});
    const auto size = [&](std::size_t d) { return stop[d] - (d == 0 ? 0 : stop[d - 1]); };
    std::stable_sort(parts.begin(), parts.end(),
                     [&](std::size_t x, std::size_t y) { return size(x) > size(y); });
    std::atomic<std::size_t> next{0};
    parallel_for(2, 2, [&](int worker, int) {
      std::optional<KeySorter> own;
      if (worker > 0) own.emplace(n, max_scratch_, low_bit_);
      KeySorter& sorter = worker > 0 ? *own : *this;
      for (std::size_t i = next++; i < kBuckets && size(parts[i]) > 0; i = next++) {
        const std::size_t d = parts[i];
        sorter.sort(keys + (d == 0 ? 0 : stop[d - 1]), size(d));
      }
    });
  }

  void sort(std::uint64_t* keys, std::size_t n) {
    if (n < kSmall) {
      std::sort(keys, keys + n);
      return;
    }
    const auto [low, high] = std::minmax_element(keys, keys + n);
    if ((*low ^ *high) >> low_bit_ == 0) return;              // equal in every sorted bit
    const int top_bit = 63 - std::countl_zero(*low ^ *high);  // highest differing bit
    if (n <= max_scratch_) {
      sort_lsd(keys, n, top_bit);
    } else {
      split_msd(keys, n, std::max(low_bit_, top_bit - kDigitBits + 1));
    }
  }

 private:
  static constexpr int kDigitBits = 11;
  static constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  // Below this, std::sort beats LSD passes that each walk 2048 counters.
  static constexpr std::size_t kSmall = 1024;

  // Digit p holds bits [low_bit + 11 p, low_bit + 11 (p + 1)).
  void sort_lsd(std::uint64_t* keys, std::size_t n, int top_bit) {
    const int passes = (top_bit - low_bit_) / kDigitBits + 1;
    // Every pass's histogram in one read of the keys.
    std::vector<std::size_t> counts(static_cast<std::size_t>(passes) * kBuckets, 0);
    for (std::size_t i = 0; i < n; ++i) {
      for (int p = 0; p < passes; ++p) {
        ++counts[p * kBuckets + ((keys[i] >> (low_bit_ + p * kDigitBits)) & (kBuckets - 1))];
      }
    }
    buffer_.resize(n);
    std::uint64_t* from = keys;
    std::uint64_t* to = buffer_.data();
    for (int p = 0; p < passes; ++p) {
      std::size_t* count = counts.data() + p * kBuckets;
      const int shift = low_bit_ + p * kDigitBits;
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
    const std::vector<std::size_t> stop = partition(keys, n, shift);
    std::size_t begin = 0;
    for (std::size_t d = 0; d < kBuckets; ++d) {
      sort(keys + begin, stop[d] - begin);  // the part's own highest differing bit is lower
      begin = stop[d];
    }
  }

  // Puts the keys in the order of their digit at `shift`, in place; returns
  // one past each digit's range.
  static std::vector<std::size_t> partition(std::uint64_t* keys, std::size_t n, int shift) {
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
    return stop;
  }

  std::size_t max_scratch_;
  int low_bit_;
  std::vector<std::uint64_t> buffer_;
};

// The keys of a window, sorted by value part; *exact is set when every key
// holds its whole value (the dropped bits are 0, e.g. for integers).
std::vector<std::uint64_t> sorted_keys(const Window& w, const PixelKeys& keys, bool* exact,
                                       bool two_threads) {
  std::vector<std::uint64_t> sorted(w.size());
  std::uint64_t dropped = 0;
  std::size_t k = 0;
  for (int y = 0; k < sorted.size(); ++y) {
    const double* row = w.row(y);
    for (std::uint32_t x = 0; x < w.width(); ++x) {
      const std::uint64_t bits = ordered_bits(row[x]);
      dropped |= bits;
      sorted[k] = keys.key(bits, static_cast<std::uint32_t>(k));
      ++k;
    }
  }
  *exact = keys.keeps_all(dropped);
  KeySorter sorter(sorted.size(), sort_scratch_keys(sorted.size()), keys.index_bits());
  if (two_threads) {
    sorter.sort_on_two_threads(sorted.data(), sorted.size());
  } else {
    sorter.sort(sorted.data(), sorted.size());
  }
  return sorted;
}

// Sorts each run of keys with equal value parts by `less` (a strict weak
// order on keys that refines the value-part order), unless it already is.
template <typename Less>
void order_runs(std::vector<std::uint64_t>& sorted, const PixelKeys& keys, Less less) {
  const std::size_t n = sorted.size();
  std::size_t begin = 0;
  while (begin < n) {
    const std::uint64_t part = keys.value_part(sorted[begin]);
    std::size_t end = begin + 1;
    while (end < n && keys.value_part(sorted[end]) == part) ++end;
    const auto first = sorted.begin() + static_cast<std::ptrdiff_t>(begin);
    const auto last = sorted.begin() + static_cast<std::ptrdiff_t>(end);
    if (end - begin > 1 && !std::is_sorted(first, last, less)) std::sort(first, last, less);
    begin = end;
  }
}

// How many ranks ahead the passes that read or write pixels in rank order
// (scattered over the image) ask for them: without it, each waits for memory.
constexpr std::size_t kAhead = 16;

// Ranks and pixel indices are 32-bit.
constexpr std::size_t kMaxRankedPixels = std::size_t{1} << 32;

// A midway value kept in a slot of the sorted keys, as its bits.
double as_double(std::uint64_t bits) {
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
std::uint64_t as_bits(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Mean B and sum of squared deviations m2 = sum (mid_i - B)^2 of the midway
// values of ranks [begin, end), in two passes (no cancellation).
struct GroupMoments {
  double mean = 0.0;
  double m2 = 0.0;
};
GroupMoments moments(const std::vector<std::uint64_t>& mid, std::size_t begin, std::size_t end) {
  double sum = 0.0;
  for (std::size_t i = begin; i < end; ++i) sum += as_double(mid[i]);
  GroupMoments g;
  g.mean = sum / static_cast<double>(end - begin);
  for (std::size_t i = begin; i < end; ++i) {
    const double d = as_double(mid[i]) - g.mean;
    g.m2 += d * d;
  }
  return g;
}

// Calls f(begin, end) for each group of ranks, `starts` marking the first
// rank of each.
template <typename F>
void for_each_group(const std::vector<bool>& starts, F f) {
  const std::size_t n = starts.size();
  std::size_t begin = 0;
  while (begin < n) {
    std::size_t end = begin + 1;
    while (end < n && !starts[end]) ++end;
    f(begin, end);
    begin = end;
  }
}

// The value whose ordered bits these are (the inverse of ordered_bits).
double value_of_bits(std::uint64_t bits) {
  return as_double((bits >> 63) ? bits ^ (std::uint64_t{1} << 63) : ~bits);
}

// a's side of the expected midway equalization, the image sorted first:
// its groups of equal values, numbered in rank order.
struct GroundRanks {
  std::vector<std::uint32_t> group;  // by pixel
  std::vector<bool> starts;          // by rank: the rank is the first of its group
  std::vector<double> value;         // by group: its value (the sweep puts B_G there)
};

GroundRanks rank_groups(std::vector<std::uint64_t> sorted, const Window& w, const PixelKeys& keys,
                        bool exact) {
  auto bits = [&](std::uint64_t key) {
    return exact ? keys.value_part(key) : ordered_bits(w[keys.pixel(key)]);
  };
  if (!exact) {
    order_runs(sorted, keys, [&](std::uint64_t i, std::uint64_t j) { return bits(i) < bits(j); });
  }
  const std::size_t n = sorted.size();
  GroundRanks ranks;
  ranks.group.resize(n);
  ranks.starts.resize(n);
  std::size_t groups = 0;
  std::uint64_t previous = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) __builtin_prefetch(&ranks.group[keys.pixel(sorted[i + kAhead])], 1);
    const std::uint64_t key = sorted[i];
    const std::uint64_t value = bits(key);
    if (i == 0 || value != previous) {
      ranks.starts[i] = true;
      sorted[groups++] = value;  // the group values, in place of keys already read
    }
    previous = value;
    ranks.group[keys.pixel(key)] = static_cast<std::uint32_t>(groups - 1);
  }
  ranks.value.resize(groups);
  for (std::size_t k = 0; k < groups; ++k) ranks.value[k] = value_of_bits(sorted[k]);
  return ranks;
}

// a's groups without sorting, when every value of the window is an integer
// in [0, 65535] (the ground truth of an 8- or 16-bit image): a histogram
// gives each value's group number (the values in increasing order) and the
// first rank of each group. The same GroundRanks as sorting gives; false,
// with `ranks` untouched, for any other window.
constexpr std::uint32_t kIntegerLevels = 65536;

bool rank_integer_groups(const Window& w, GroundRanks& ranks) {
  std::vector<std::uint32_t> count(kIntegerLevels, 0);
  for (int y = 0; y < static_cast<int>(w.size() / w.width()); ++y) {
    const double* row = w.row(y);
    for (std::uint32_t x = 0; x < w.width(); ++x) {
      const double v = row[x];
      if (!(v >= 0.0 && v < kIntegerLevels) || v != std::floor(v)) return false;
      ++count[static_cast<std::uint32_t>(v)];
    }
  }
  std::vector<std::uint32_t> group_of(kIntegerLevels);
  ranks.starts.assign(w.size(), false);
  ranks.value.clear();
  std::size_t rank = 0;
  for (std::uint32_t level = 0; level < kIntegerLevels; ++level) {
    if (count[level] == 0) continue;
    group_of[level] = static_cast<std::uint32_t>(ranks.value.size());
    ranks.value.push_back(static_cast<double>(level));
    ranks.starts[rank] = true;
    rank += count[level];
  }
  ranks.group.resize(w.size());
  std::size_t p = 0;
  for (int y = 0; p < w.size(); ++y) {
    const double* row = w.row(y);
    for (std::uint32_t x = 0; x < w.width(); ++x) {
      ranks.group[p++] = group_of[static_cast<std::uint32_t>(row[x])];
    }
  }
  return true;
}

// Puts b's sorted keys in the exact order of their values, and equal values
// in the order of a's groups at their pixels: the ranks then list the
// (b value, a value) pairs in lexicographic order, whatever the pixel order.
void order_restored(std::vector<std::uint64_t>& sorted, const Window& w, const PixelKeys& keys,
                    bool exact, const GroundRanks& a) {
  auto bits = [&](std::uint64_t key) {
    return exact ? keys.value_part(key) : ordered_bits(w[keys.pixel(key)]);
  };
  order_runs(sorted, keys, [&](std::uint64_t i, std::uint64_t j) {
    const std::uint32_t pi = keys.pixel(i);
    const std::uint32_t pj = keys.pixel(j);
    const std::uint64_t bi = bits(i);
    const std::uint64_t bj = bits(j);
    return bi < bj || (bi == bj && a.group[pi] < a.group[pj]);
  });
}

// The expected squared difference of the midway-equalized windows a and b of
// one channel, summed over the pixels, over independent uniform orders of
// each group of equal values of a and of b (docs/method.md §5). Pixel p of
// a's group G and b's group H: E[(a'_p - b'_p)^2] = A_G - 2 B_G B_H + A_H,
// with B and A the means of mid_i and mid_i^2 over the group's ranks, i.e.
// (A_G - B_G^2) + (A_H - B_H^2) + (B_G - B_H)^2. The sum is taken as
// sum_G m2_G + sum_H m2_H + sum_p (B_G - B_H)^2 (m2: the group's sum of
// squared deviations of mid from its mean), each in an order fixed by the
// values alone, so the result does not depend on the order of the pixels.
class ExpectedMidwaySum {
 public:
  // With two `workers`, a and b are ranked at the same time when the window
  // is small (in_parallel), else b's sort and the passes over the ranks use
  // both.
  ExpectedMidwaySum(const Window& a, const Window& b, bool in_parallel, int workers)
      : workers_(workers > 1 ? 2 : 1) {
    const std::size_t n = a.size();
    if (n > kMaxRankedPixels) {
      throw_usage_error("a window of " + std::to_string(n) +
                        " pixels a channel is too large to rank: at most 2^32 are supported");
    }
    const PixelKeys keys(n);
    bool b_exact = false;
    std::future<std::vector<std::uint64_t>> b_sorted;
    if (in_parallel) {
      try {
        b_sorted =
            std::async(std::launch::async, [&] { return sorted_keys(b, keys, &b_exact, false); });
      } catch (const std::system_error&) {
        // no thread: sort b after a
      }
    }
    GroundRanks ranks;
    if (!rank_integer_groups(a, ranks)) {
      bool a_exact = false;
      ranks = rank_groups(sorted_keys(a, keys, &a_exact, workers_ > 1 && !b_sorted.valid()), a,
                          keys, a_exact);
    }
    std::vector<std::uint64_t> sorted =
        b_sorted.valid() ? b_sorted.get() : sorted_keys(b, keys, &b_exact, workers_ > 1);
    order_restored(sorted, b, keys, b_exact, ranks);
    const double m2_sum = sweep(b, keys, ranks, sorted);
    sum_ = m2_sum + cross_sum(ranks, sorted);
  }
  double sum() const { return sum_; }

 private:
  double sweep(const Window& b, const PixelKeys& keys, GroundRanks& ranks,
               std::vector<std::uint64_t>& sorted);
  double cross_sum(const GroundRanks& ranks, std::vector<std::uint64_t>& b_means) const;

  // Below twice this many ranks, the passes over them stay on one thread.
  static constexpr std::size_t kChunkRanks = std::size_t{1} << 16;
  int workers_;                         // threads of the passes over the ranks: 1 or 2
  std::vector<std::uint32_t> b_pixel_;  // by rank
  double sum_ = 0.0;
};

// mid_i for every rank, then the moments of a's and b's groups: returns
// sum m2 over both sides' groups (a's, then b's). Leaves B_G in
// ranks.value, b's pixel of each rank in b_pixel_ and B_H of each rank in
// `sorted` (as bits).
double ExpectedMidwaySum::sweep(const Window& b, const PixelKeys& keys, GroundRanks& ranks,
                                std::vector<std::uint64_t>& sorted) {
  const std::size_t n = sorted.size();
  b_pixel_.resize(n);
  std::vector<bool> b_starts(n);
  // The ranks in `chunks` ranges on as many threads; each range starts at a
  // multiple of 64 (its own words of b_starts), knowing a's group there and
  // the bits of the previous rank's b value (read before any is written).
  const std::size_t chunks = n >= 2 * kChunkRanks ? static_cast<std::size_t>(workers_) : 1;
  std::vector<std::size_t> bounds(chunks + 1, n);
  std::vector<std::size_t> first_group(chunks, 0);
  std::vector<std::uint64_t> previous_bits(chunks, 0);
  for (std::size_t c = 0; c < chunks; ++c) {
    bounds[c] = n * c / chunks / 64 * 64;
    if (c == 0) continue;
    first_group[c] = static_cast<std::size_t>(std::count(
                         ranks.starts.begin(),
                         ranks.starts.begin() + static_cast<std::ptrdiff_t>(bounds[c]) + 1, true)) -
                     1;
    previous_bits[c] = ordered_bits(b[keys.pixel(sorted[bounds[c] - 1])]);
  }
  parallel_for(static_cast<int>(chunks), static_cast<int>(chunks), [&](int c, int) {
    const std::size_t begin = bounds[c];
    const std::size_t end = bounds[c + 1];
    std::size_t a_group = first_group[c];
    std::uint64_t previous = previous_bits[c];
    for (std::size_t i = begin; i < end; ++i) {
      if (i + kAhead < end) __builtin_prefetch(b.address(keys.pixel(sorted[i + kAhead])));
      if (i > begin && ranks.starts[i]) ++a_group;
      const std::uint32_t pixel = keys.pixel(sorted[i]);
      const double vb = b[pixel];
      b_starts[i] = i == 0 || ordered_bits(vb) != previous;
      previous = ordered_bits(vb);
      b_pixel_[i] = pixel;
      sorted[i] = as_bits(0.5 * (ranks.value[a_group] + vb));  // mid_i: the two i-th smallest' mean
    }
  });
  double m2_sum = 0.0;
  std::size_t k = 0;
  for_each_group(ranks.starts, [&](std::size_t begin, std::size_t end) {
    const GroupMoments g = moments(sorted, begin, end);
    ranks.value[k++] = g.mean;
    m2_sum += g.m2;
  });
  for_each_group(b_starts, [&](std::size_t begin, std::size_t end) {
    if (end - begin == 1) return;  // B_H = mid_i, m2 = 0
    const GroupMoments g = moments(sorted, begin, end);
    std::fill(sorted.begin() + static_cast<std::ptrdiff_t>(begin),
              sorted.begin() + static_cast<std::ptrdiff_t>(end), as_bits(g.mean));
    m2_sum += g.m2;
  });
  return m2_sum;
}

// sum_p (B_G - B_H)^2 in b's rank order (b's ties in the order of a's
// groups). The squares are computed on the threads, in place of the B_H
// they were made from, and summed in rank order: the bits of one thread.
double ExpectedMidwaySum::cross_sum(const GroundRanks& ranks,
                                    std::vector<std::uint64_t>& b_means) const {
  const std::size_t n = b_means.size();
  const int chunks = n >= 2 * kChunkRanks ? workers_ : 1;
  parallel_for(chunks, chunks, [&](int c, int) {
    const std::size_t begin = n * static_cast<std::size_t>(c) / static_cast<std::size_t>(chunks);
    const std::size_t end = n * static_cast<std::size_t>(c + 1) / static_cast<std::size_t>(chunks);
    for (std::size_t i = begin; i < end; ++i) {
      if (i + kAhead < end) __builtin_prefetch(&ranks.group[b_pixel_[i + kAhead]]);
      const double d = ranks.value[ranks.group[b_pixel_[i]]] - as_double(b_means[i]);
      b_means[i] = as_bits(d * d);
    }
  });
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += as_double(b_means[i]);
  return sum;
}

// The group means of the midway values of a sorted sample: element i is
// B of the group of equal values holding rank i (bits compared, -0 = +0).
std::vector<double> group_means(const std::vector<double>& sorted, const std::vector<double>& mid) {
  std::vector<double> means(sorted.size());
  std::size_t begin = 0;
  while (begin < sorted.size()) {
    std::size_t end = begin + 1;
    while (end < sorted.size() && ordered_bits(sorted[end]) == ordered_bits(sorted[begin])) ++end;
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) sum += mid[i];
    std::fill(means.begin() + static_cast<std::ptrdiff_t>(begin),
              means.begin() + static_cast<std::ptrdiff_t>(end),
              sum / static_cast<double>(end - begin));
    begin = end;
  }
  return means;
}

bool ordered_less(double x, double y) { return ordered_bits(x) < ordered_bits(y); }

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

double rmse_contrast_invariant(const Image& a, int a_offset, const Image& b, int first, int end,
                               int threads) {
  require_aligned(a, a_offset, b);
  require_window(b, first, end);
  const std::size_t window = static_cast<std::size_t>(end - first) * b.height;
  const int workers = resolve_thread_count(threads);
  const bool in_parallel = workers > 1 && window <= kParallelSortPixels;
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    sum += ExpectedMidwaySum(Window(&a, c, first + a_offset, end + a_offset),
                             Window(&b, c, first, end), in_parallel, workers)
               .sum();
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
