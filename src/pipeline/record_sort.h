// Sorting the 16-byte records of RMSE_CI (expected_midway.cpp): a bucket
// sort whose buckets come from the values themselves (linear in the value
// between the smallest and the largest, so the buckets of image data are
// about equally full), sorted in cache. Internal to the library.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "core/huge_pages.h"

namespace fss::midway {

// The order-preserving bits of a value: comparing two as unsigned integers
// compares the values (-0 and +0 are the same value).
inline std::uint64_t ordered_bits(double value) {
  if (value == 0.0) value = 0.0;
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  // Flip all bits of negatives, the sign bit of positives.
  const auto negative = static_cast<std::uint64_t>(static_cast<std::int64_t>(bits) >> 63);
  return bits ^ (negative | (std::uint64_t{1} << 63));
}

// The value whose ordered bits these are (-0 comes back as +0).
inline double value_of_bits(std::uint64_t bits) {
  const auto positive = static_cast<std::uint64_t>(static_cast<std::int64_t>(bits) >> 63);
  bits ^= ~positive | (std::uint64_t{1} << 63);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// A key (the ordered bits of a value) and a tie-breaker (a group number).
struct Record {
  std::uint64_t key;
  std::uint64_t tie;
};

// Uninitialized storage for n records, and kPrefetchSlack more that a
// prefetch ahead of the last record may point at; asked for on huge pages
// (madvise) when there are many: the records are written to a thousand
// places at once (the scatter), which with 4 KiB pages misses the TLB.
inline constexpr std::size_t kPrefetchSlack = 8;

// From 1 MiB on huge pages (detail::allocate_buffer): fewer page faults, and fewer TLB misses
// in the scatter (CONTRIBUTING.md, "Hand-written fast paths").
class RecordBuffer {
 public:
  explicit RecordBuffer(std::size_t n) : records_(n + kPrefetchSlack) {}
  Record* data() { return records_.data(); }

 private:
  detail::BufferArray<Record> records_;
};

// A monotone map of the keys in [low, high] onto buckets 0 .. count() - 1
// that sends `low` to the first and `high` to the last, so that a range of
// different keys is always split. Ordered bits of values are mapped
// linearly in the value when the range allows it (finite, and not so small
// that the scale overflows); other keys, linearly in their bits.
class BucketMap {
 public:
  static BucketMap of_values(std::uint64_t low, std::uint64_t high, std::size_t buckets);
  static BucketMap of_integers(std::uint64_t low, std::uint64_t high, std::size_t buckets);

  std::size_t operator()(std::uint64_t key) const {
    return by_value_ ? of_value(value_of_bits(key)) : of_bits(key);
  }
  // The same as (*this)(ordered_bits(value)), without the bits.
  std::size_t of_value_bits(double value) const {
    return by_value_ ? of_value(value) : of_bits(ordered_bits(value));
  }
  std::size_t count() const { return last_ + 1; }

 private:
  // (value - low) * buckets / (high - low), rounded down: monotone, as
  // every rounding is; -0 and +0 land in the same bucket (-0 - low is -low,
  // or -0 when low is +0).
  std::size_t of_value(double value) const {
    const double x = (value - low_value_) * scale_;
    return std::min(last_, static_cast<std::size_t>(static_cast<std::int64_t>(x)));
  }
  std::size_t of_bits(std::uint64_t key) const {
    return static_cast<std::size_t>((key - low_) >> shift_);
  }

  bool by_value_ = false;
  double low_value_ = 0.0;
  double scale_ = 0.0;
  std::uint64_t low_ = 0;
  int shift_ = 0;
  std::size_t last_ = 0;
};

// The buckets of a whole window: linear in the value between two quantiles
// of a sample of the keys (the 1/1024-th from each end), with one more
// bucket below and one above, so that a few extreme values (a pixel at
// 1e150) do not crowd all the others into one bucket. Monotone in the key;
// equal keys share a bucket.
class TopBuckets {
 public:
  TopBuckets(std::vector<std::uint64_t> sample, std::size_t buckets);
  std::size_t of_key(std::uint64_t key) const {
    if (key < low_) return 0;
    if (key > high_) return last_;
    return 1 + inner_(key);
  }
  // The same as of_key(ordered_bits(value)).
  std::size_t of_value(double value) const {
    const std::uint64_t key = ordered_bits(value);
    if (key < low_) return 0;
    if (key > high_) return last_;
    return 1 + inner_.of_value_bits(value);
  }
  std::size_t count() const { return last_ + 1; }

 private:
  std::uint64_t low_ = 0;
  std::uint64_t high_ = 0;
  BucketMap inner_;
  std::size_t last_ = 0;
};

// Sorts records by key and tie (kTies) or by key alone, in place. A range
// of at most `capacity` records (one that fits in cache) is distributed
// through a buffer (as large as the largest range yet) into two buckets per
// record, by the
// BucketMap of its own smallest and largest key, and comes back with an
// insertion sort on the way (buckets of more than a few records are first
// sorted the same way). A range of equal keys is sorted by tie the same
// way. A longer range is first split in place (each misplaced record
// cycled to the next free slot of its bucket). Ranges still unsorted after
// kMaxDepth splits (only adversarial values, such as powers of two, get
// there) are handed to std::sort (the choices: CONTRIBUTING.md, "Hand-written
// fast paths").
template <bool kTies>
class RecordSorter {
 public:
  explicit RecordSorter(std::size_t capacity);
  void sort(Record* records, std::size_t n) { sort_on<false>(records, n, 0); }

 private:
  static constexpr std::size_t kInsertion = 16;
  static constexpr int kMaxDepth = 16;
  static constexpr std::size_t kSplitBuckets = 4096;

  template <bool kOnTie>
  void sort_on(Record* records, std::size_t n, int depth);
  template <bool kOnTie>
  void distribute(Record* records, std::size_t n, const BucketMap& map, int depth);
  template <bool kOnTie>
  void split_in_place(Record* records, std::size_t n, const BucketMap& map, int depth);

  void reserve();

  std::size_t capacity_;
  std::unique_ptr<detail::HugePageBuffer> storage_;
  Record* buffer_ = nullptr;
  std::uint32_t* bucket_ = nullptr;   // each record's bucket, while distributing
  std::vector<std::uint32_t> start_;  // each bucket's first slot, while distributing
};

// Puts the records in the order of the buckets of their keys, in place;
// returns the first record of each bucket and one past the last.
std::vector<std::size_t> partition_by_key(Record* records, std::size_t n,
                                          const TopBuckets& buckets);

extern template class RecordSorter<true>;
extern template class RecordSorter<false>;

}  // namespace fss::midway
