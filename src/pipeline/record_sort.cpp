#include "pipeline/record_sort.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>

#include "core/huge_pages.h"

namespace fss::midway {

BucketMap BucketMap::of_values(std::uint64_t low, std::uint64_t high, std::size_t buckets) {
  const double low_value = value_of_bits(low);
  const double range = value_of_bits(high) - low_value;
  const double scale = static_cast<double>(buckets) / range;
  // range * (buckets / range) >= buckets (1 - 2^-52)^2 > buckets - 1: the
  // highest key reaches the last bucket.
  if (buckets < 2 || !(range > 0.0) || !std::isfinite(range) || !std::isfinite(scale)) {
    return of_integers(low, high, buckets);
  }
  BucketMap map;
  map.by_value_ = true;
  map.low_value_ = low_value;
  map.scale_ = scale;
  map.last_ = buckets - 1;
  return map;
}

BucketMap BucketMap::of_integers(std::uint64_t low, std::uint64_t high, std::size_t buckets) {
  BucketMap map;
  map.low_ = low;
  const int kept = std::bit_width(std::max<std::size_t>(buckets, 1)) - 1;  // floor(log2)
  // At most 63: one bucket asked of keys 2^63 apart gives two.
  map.shift_ = std::clamp(static_cast<int>(std::bit_width(high - low)) - kept, 0, 63);
  map.last_ = static_cast<std::size_t>((high - low) >> map.shift_);
  return map;
}

namespace {

template <bool kTies>
bool less(const Record& x, const Record& y) {
  if constexpr (kTies) {
    return x.key < y.key || (x.key == y.key && x.tie < y.tie);
  } else {
    return x.key < y.key;
  }
}

template <bool kOnTie>
std::uint64_t field(const Record& r) {
  if constexpr (kOnTie) {
    return r.tie;
  } else {
    return r.key;
  }
}

// The smallest and largest field of the records (a plain loop: twice as
// fast as std::minmax_element here).
template <bool kOnTie>
std::pair<std::uint64_t, std::uint64_t> field_range(const Record* r, std::size_t n) {
  std::uint64_t low = ~std::uint64_t{0};
  std::uint64_t high = 0;
  for (std::size_t i = 0; i < n; ++i) {
    low = std::min(low, field<kOnTie>(r[i]));
    high = std::max(high, field<kOnTie>(r[i]));
  }
  return {low, high};
}

// Insertion sort of `from` into `to`: sorts records that are already in the
// order of their buckets, moving each back inside its own bucket only.
template <bool kTies>
void insertion_copy(const Record* from, Record* to, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const Record x = from[i];
    std::size_t j = i;
    while (j > 0 && less<kTies>(x, to[j - 1])) {
      to[j] = to[j - 1];
      --j;
    }
    to[j] = x;
  }
}

template <bool kTies>
void insertion_sort(Record* r, std::size_t n) {
  for (std::size_t i = 1; i < n; ++i) {
    if (!less<kTies>(r[i], r[i - 1])) continue;
    const Record x = r[i];
    std::size_t j = i;
    do {
      r[j] = r[j - 1];
      --j;
    } while (j > 0 && less<kTies>(x, r[j - 1]));
    r[j] = x;
  }
}

// Puts the records in the order of their buckets, bucket(record) among m,
// in place, "American flag" style: every record is cycled to the next free
// slot of its bucket. Returns the first record of each bucket and one past
// the last.
template <typename Bucket>
std::vector<std::size_t> partition(Record* r, std::size_t n, std::size_t m, Bucket bucket) {
  std::vector<std::size_t> bounds(m + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++bounds[bucket(r[i]) + 1];
  for (std::size_t b = 0; b < m; ++b) bounds[b + 1] += bounds[b];
  std::vector<std::size_t> next(bounds.begin(), bounds.end() - 1);  // each bucket's next free slot
  for (std::size_t b = 0; b < m; ++b) {
    while (next[b] < bounds[b + 1]) {
      Record x = r[next[b]];
      std::size_t home = bucket(x);
      while (home != b) {
        std::swap(x, r[next[home]++]);
        home = bucket(x);
      }
      r[next[b]++] = x;
    }
  }
  return bounds;
}

}  // namespace

template <bool kTies>
RecordSorter<kTies>::RecordSorter(std::size_t capacity)
    : capacity_(std::max<std::size_t>(capacity, kInsertion)) {}

// The buffers for ranges of up to capacity_ records, at the first range that needs them: on
// huge pages (core/huge_pages.h), so that they cost one page fault or two, not one per 4 KiB.
template <bool kTies>
void RecordSorter<kTies>::reserve() {
  if (storage_ != nullptr) return;
  storage_ = std::make_unique<detail::HugePageBuffer>(capacity_ *
                                                      (sizeof(Record) + sizeof(std::uint32_t)));
  buffer_ = reinterpret_cast<Record*>(storage_->data());
  bucket_ = reinterpret_cast<std::uint32_t*>(storage_->data() + capacity_ * sizeof(Record));
}

template <bool kTies>
template <bool kOnTie>
void RecordSorter<kTies>::sort_on(Record* r, std::size_t n, int depth) {
  if (n <= kInsertion) {
    insertion_sort<kTies>(r, n);
    return;
  }
  const auto [low, high] = field_range<kOnTie>(r, n);
  if (low == high) {
    if constexpr (kTies && !kOnTie) sort_on<true>(r, n, depth);
    return;
  }
  if (depth >= kMaxDepth) {
    std::sort(r, r + n, less<kTies>);
    return;
  }
  const std::size_t buckets = n > capacity_ ? kSplitBuckets : 2 * n;
  const BucketMap map = kOnTie ? BucketMap::of_integers(low, high, buckets)
                               : BucketMap::of_values(low, high, buckets);
  if (n > capacity_) {
    split_in_place<kOnTie>(r, n, map, depth);
  } else {
    distribute<kOnTie>(r, n, map, depth);
  }
}

// Through the buffer: the bucket of each record, the counts, the records in
// bucket order; then back in place with an insertion sort on the way (no
// record moves out of its bucket), unless a bucket holds more than
// kInsertion records: then the records go back as they are, those buckets
// are sorted the same way, and an insertion pass sorts the small ones.
template <bool kTies>
template <bool kOnTie>
void RecordSorter<kTies>::distribute(Record* r, std::size_t n, const BucketMap& map, int depth) {
  const std::size_t m = map.count();
  reserve();
  start_.assign(m + 1, 0);
  std::uint32_t* start = start_.data();
  bool small = true;  // every bucket holds at most kInsertion records
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = static_cast<std::uint32_t>(map(field<kOnTie>(r[i])));
    bucket_[i] = b;
    small &= ++start[b + 1] <= kInsertion;
  }
  for (std::size_t b = 0; b < m; ++b) start[b + 1] += start[b];
  for (std::size_t i = 0; i < n; ++i) buffer_[start[bucket_[i]]++] = r[i];
  if (small) {
    insertion_copy<kTies>(buffer_, r, n);
    return;
  }
  std::copy(buffer_, buffer_ + n, r);
  // start_[b] is now the end of bucket b.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> large;
  for (std::size_t b = 0, begin = 0; b < m; begin = start_[b++]) {
    if (start_[b] - begin > kInsertion) large.emplace_back(begin, start_[b] - begin);
  }
  for (const auto& [begin, size] : large) sort_on<kOnTie>(r + begin, size, depth + 1);
  insertion_sort<kTies>(r, n);
}

template <bool kTies>
template <bool kOnTie>
void RecordSorter<kTies>::split_in_place(Record* r, std::size_t n, const BucketMap& map,
                                         int depth) {
  const std::vector<std::size_t> bounds =
      partition(r, n, map.count(), [&](const Record& x) { return map(field<kOnTie>(x)); });
  for (std::size_t b = 0; b + 1 < bounds.size(); ++b) {
    sort_on<kOnTie>(r + bounds[b], bounds[b + 1] - bounds[b], depth + 1);
  }
}

std::vector<std::size_t> partition_by_key(Record* records, std::size_t n,
                                          const TopBuckets& buckets) {
  return partition(records, n, buckets.count(),
                   [&](const Record& x) { return buckets.of_key(x.key); });
}

TopBuckets::TopBuckets(std::vector<std::uint64_t> sample, std::size_t buckets) {
  const std::size_t tail = sample.size() / 1024;
  const auto low = sample.begin() + static_cast<std::ptrdiff_t>(tail);
  const auto high = sample.end() - 1 - static_cast<std::ptrdiff_t>(tail);
  std::nth_element(sample.begin(), low, sample.end());
  low_ = *low;
  std::nth_element(low, high, sample.end());  // may move *low: read before
  high_ = *high;
  inner_ = BucketMap::of_values(low_, high_, std::max<std::size_t>(buckets, 3) - 2);
  last_ = inner_.count() + 1;
}

template class RecordSorter<true>;
template class RecordSorter<false>;

}  // namespace fss::midway
