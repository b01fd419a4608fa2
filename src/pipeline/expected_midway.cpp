#include "pipeline/expected_midway.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/huge_pages.h"
#include "core/parallel.h"

namespace fss::midway {

namespace {

// The records of b's pixels are scattered into buckets of about
// kBucketRecords (128 KiB: sorted in the level-2 cache); one thread's
// buffer sorts at most kSortCapacity of them (larger buckets are split in
// place first). The sizes: CONTRIBUTING.md, "Hand-written fast paths".
constexpr std::size_t kBucketRecords = 8192;
constexpr std::size_t kSortCapacity = 32768;

// Set in Record::tie at the first rank of each run of equal b values.
constexpr std::uint64_t kRunStart = std::uint64_t{1} << 63;

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

// The first ranks of a's groups, set in increasing order: a sorted list
// when there are few groups (8 bytes each: 2 KiB for 8-bit images), else
// one bit per rank (n / 8 bytes, 1.4 MB for 11 Mpx).
class GroupStarts {
 public:
  GroupStarts() = default;
  GroupStarts(std::size_t n, std::size_t groups) : n_(n), listed_(groups * 64 < n) {
    if (listed_) {
      list_.reserve(groups);
    } else {
      words_.assign((n + 63) / 64, 0);
    }
  }
  void set(std::size_t i) {
    if (listed_) {
      list_.push_back(i);
    } else {
      words_[i >> 6] |= std::uint64_t{1} << (i & 63);
    }
  }
  // The first start at or after i, or n.
  std::size_t next(std::size_t i) const {
    if (i >= n_) return n_;
    if (listed_) {
      const auto found = std::lower_bound(list_.begin(), list_.end(), i);
      return found == list_.end() ? n_ : *found;
    }
    std::size_t w = i >> 6;
    std::uint64_t word = words_[w] & (~std::uint64_t{0} << (i & 63));
    while (word == 0) {
      if (++w == words_.size()) return n_;
      word = words_[w];
    }
    return std::min(n_, (w << 6) + static_cast<std::size_t>(std::countr_zero(word)));
  }
  // How many starts are before i (the group holding rank i, if i starts one).
  std::size_t count_before(std::size_t i) const {
    if (listed_) {
      return static_cast<std::size_t>(std::lower_bound(list_.begin(), list_.end(), i) -
                                      list_.begin());
    }
    std::size_t count = 0;
    for (std::size_t w = 0; w < i >> 6; ++w) {
      count += static_cast<std::size_t>(std::popcount(words_[w]));
    }
    if ((i & 63) != 0) {
      const std::uint64_t below = (std::uint64_t{1} << (i & 63)) - 1;
      count += static_cast<std::size_t>(std::popcount(words_[i >> 6] & below));
    }
    return count;
  }

 private:
  std::size_t n_ = 0;
  bool listed_ = true;
  std::vector<std::size_t> list_;
  std::vector<std::uint64_t> words_;
};

// a's side: its groups of equal values, numbered in rank order.
struct GroundGroups {
  std::vector<double> value;  // by group: its value, then B_G
  GroupStarts starts;         // the first rank of each group
};

// Rows [first, end) of worker w of `workers`.
std::pair<std::uint32_t, std::uint32_t> rows_of(std::uint32_t height, int w, int workers) {
  const auto share = [&](int k) {
    return static_cast<std::uint32_t>(std::uint64_t{height} * static_cast<std::uint64_t>(k) /
                                      static_cast<std::uint64_t>(workers));
  };
  return {share(w), share(w + 1)};
}

// ---- The top-level buckets: a sample of the keys ----

// The top-level buckets of a window's values, from the keys of
// kSampleSize of its pixels, evenly spaced (read out of order before any
// pass over the window: a few hundred microseconds; the passes then count
// the buckets as they go).
constexpr std::size_t kSampleSize = 4096;

TopBuckets top_buckets(const ChannelWindow& v) {
  const std::size_t n = v.size();
  std::vector<std::uint64_t> keys(std::min(n, kSampleSize));
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::size_t p = k * n / keys.size();
    keys[k] = ordered_bits(v.row(static_cast<std::uint32_t>(p / v.width))[p % v.width]);
  }
  return TopBuckets(std::move(keys), n / kBucketRecords);
}

// Each worker's count of the pixels of its rows in each top-level bucket.
using BucketCounts = std::vector<std::vector<std::size_t>>;

// The BucketCounts of a window's values.
BucketCounts count_buckets(const ChannelWindow& v, const TopBuckets& top, int workers) {
  BucketCounts counts(static_cast<std::size_t>(workers), std::vector<std::size_t>(top.count(), 0));
  parallel_for(workers, workers, [&](int w, int) {
    std::size_t* count = counts[static_cast<std::size_t>(w)].data();
    const auto [y0, y1] = rows_of(v.height, w, workers);
    for (std::uint32_t y = y0; y < y1; ++y) {
      const double* row = v.row(y);
      for (std::uint32_t x = 0; x < v.width; ++x) ++count[top.of_value(row[x])];
    }
  });
  return counts;
}

// ---- a's groups on a lattice: a histogram ----

// The levels of an 8- or 16-bit ground truth (image.h): the integers k in
// [0, 65535], or k / 257 (kPer257: 16-bit images). level(v) is kLevels off
// the lattice.
constexpr std::uint32_t kLevels = 65536;

const std::array<double, kLevels>& per_257_table() {
  static const std::array<double, kLevels> table = [] {
    std::array<double, kLevels> values{};
    for (std::uint32_t k = 0; k < kLevels; ++k) values[k] = k / 257.0;
    return values;
  }();
  return table;
}

template <bool kPer257>
class Lattice {
 public:
  Lattice() : table_(kPer257 ? per_257_table().data() : nullptr) {}
  std::uint32_t level(double v) const {
    if constexpr (!kPer257) {
      if (!(v >= 0.0 && v < 65536.0)) return kLevels;
      const auto k = static_cast<std::uint32_t>(v);
      return static_cast<double>(k) == v ? k : kLevels;
    } else {
      if (!(v >= 0.0 && v <= 255.0)) return kLevels;
      // v = k / 257 (1 + e), |e| <= 2^-53: v * 257 is within 1e-11 of k, so
      // adding 0.5 and truncating finds k.
      const auto k =
          static_cast<std::uint32_t>(v * 257.0 + 0.5);  // NOLINT(bugprone-incorrect-roundings)
      return table_[k] == v ? k : kLevels;
    }
  }
  // The level of v, known to be on the lattice.
  std::uint32_t known_level(double v) const {
    if constexpr (!kPer257) {
      return static_cast<std::uint32_t>(v);
    } else {
      return static_cast<std::uint32_t>(v * 257.0 + 0.5);  // NOLINT(bugprone-incorrect-roundings)
    }
  }
  double value(std::uint32_t k) const {
    if constexpr (kPer257) {
      return table_[k];
    } else {
      return static_cast<double>(k);
    }
  }

 private:
  const double* table_;
};

// How many pixels of some rows hold each level of a, the lowest and
// highest level held, and how many of b's values fall in each top-level
// bucket.
struct LevelCounts {
  explicit LevelCounts(std::size_t buckets) : bucket(buckets, 0) {}
  detail::ZeroedArray<std::uint64_t> count{kLevels};  // pages touched by the levels held only
  std::uint32_t low = kLevels;
  std::uint32_t high = 0;
  std::vector<std::size_t> bucket;
};

// Counts the levels of a's rows [y0, y1) and b's buckets; false at the
// first value of a off the lattice. (Locals, not members, in the loop: the
// stores to the counts could alias members.)
template <typename Lattice>
bool count_levels(const ChannelWindow& a, const ChannelWindow& b, const Lattice& lattice,
                  const TopBuckets& top, std::uint32_t y0, std::uint32_t y1, LevelCounts& counts) {
  std::uint64_t* count = counts.count.data();
  std::size_t* bucket = counts.bucket.data();
  std::uint32_t low = counts.low;
  std::uint32_t high = counts.high;
  for (std::uint32_t y = y0; y < y1; ++y) {
    const double* ra = a.row(y);
    const double* rb = b.row(y);
    for (std::uint32_t x = 0; x < a.width; ++x) {
      const std::uint32_t k = lattice.level(ra[x]);
      if (k == kLevels) return false;
      ++count[k];
      low = std::min(low, k);
      high = std::max(high, k);
      ++bucket[top.of_value(rb[x])];
    }
  }
  counts.low = low;
  counts.high = high;
  return true;
}

// The level counts of all of a (in the first worker's), or nothing when a
// value is off the lattice.
template <typename Lattice>
std::optional<std::vector<LevelCounts>> count_all_levels(const ChannelWindow& a,
                                                         const ChannelWindow& b,
                                                         const Lattice& lattice,
                                                         const TopBuckets& top, int workers) {
  std::vector<LevelCounts> counts;
  counts.reserve(static_cast<std::size_t>(workers));
  for (int w = 0; w < workers; ++w) counts.emplace_back(top.count());
  std::atomic<bool> on_lattice{true};
  parallel_for(workers, workers, [&](int w, int) {
    const auto [y0, y1] = rows_of(a.height, w, workers);
    if (!count_levels(a, b, lattice, top, y0, y1, counts[static_cast<std::size_t>(w)])) {
      on_lattice = false;
    }
  });
  if (!on_lattice) return std::nullopt;
  LevelCounts& all = counts[0];
  for (std::size_t w = 1; w < counts.size(); ++w) {
    const LevelCounts& part = counts[w];
    for (std::uint32_t k = part.low; k <= part.high; ++k) all.count[k] += part.count[k];
    all.low = std::min(all.low, part.low);
    all.high = std::max(all.high, part.high);
  }
  return counts;
}

// a's groups from its level counts: one per level held, numbered in level
// order (the order of the values). Returns the group of each level held.
template <typename Lattice>
std::unique_ptr<std::uint32_t[]> groups_from_counts(const LevelCounts& counts,
                                                    const Lattice& lattice, std::size_t n,
                                                    GroundGroups& groups) {
  auto group_of = std::make_unique_for_overwrite<std::uint32_t[]>(kLevels);
  const auto held = static_cast<std::size_t>(std::count_if(counts.count.data() + counts.low,
                                                           counts.count.data() + counts.high + 1,
                                                           [](std::uint64_t c) { return c > 0; }));
  groups.starts = GroupStarts(n, held);
  groups.value.clear();
  std::size_t rank = 0;
  for (std::uint32_t k = counts.low; k <= counts.high; ++k) {
    if (counts.count[k] == 0) continue;
    group_of[k] = static_cast<std::uint32_t>(groups.value.size());
    groups.value.push_back(lattice.value(k));
    groups.starts.set(rank);
    rank += counts.count[k];
  }
  return group_of;
}

// ---- The records, scattered into the top-level buckets ----

// Records of the pixels, made by make(a value, b value), put into the `top`
// buckets of the values of `keys` (a or b), in any order inside a bucket,
// `counts` of them in each bucket from each worker's rows; returns the
// first record of each bucket and one past the last. The pixels are read
// in order, and the records go to a thousand places at once.
template <typename MakeRecord>
std::vector<std::size_t> place(const ChannelWindow& a, const ChannelWindow& b,
                               const ChannelWindow& keys, MakeRecord make, const TopBuckets& top,
                               BucketCounts counts, Record* records, int workers) {
  const std::size_t m = top.count();
  std::vector<std::size_t> bounds(m + 1, 0);
  for (std::size_t k = 0, start = 0; k < m; ++k) {
    bounds[k] = start;
    for (auto& count : counts) start += std::exchange(count[k], start);  // the worker's first slot
    bounds[k + 1] = start;
  }
  parallel_for(workers, workers, [&](int w, int) {
    std::size_t* slot = counts[static_cast<std::size_t>(w)].data();
    const auto [y0, y1] = rows_of(a.height, w, workers);
    for (std::uint32_t y = y0; y < y1; ++y) {
      const double* ra = a.row(y);
      const double* rb = b.row(y);
      const double* rk = keys.row(y);
      for (std::uint32_t x = 0; x < a.width; ++x) {
        const std::size_t s = slot[top.of_value(rk[x])]++;
        // The bucket's line after next, asked for ahead (a hand-written
        // prefetch, CONTRIBUTING.md "Hand-written fast paths"; RecordBuffer
        // holds kPrefetchSlack records more).
        __builtin_prefetch(records + s + kPrefetchSlack, 1);
        records[s] = make(ra[x], rb[x]);
      }
    }
  });
  return bounds;
}

// When every value of a is on `lattice`: a's groups from a histogram, and
// the records (b's key, a's group) scattered into the buckets of b's
// values, whose bounds go to `parts`. False, with nothing done, otherwise.
template <typename Lattice>
bool rank_on(const Lattice& lattice, const ChannelWindow& a, const ChannelWindow& b,
             const TopBuckets& top, Record* records, GroundGroups& groups,
             std::vector<std::size_t>& parts, int workers) {
  std::optional<std::vector<LevelCounts>> counts = count_all_levels(a, b, lattice, top, workers);
  if (!counts) return false;
  const auto group_of = groups_from_counts((*counts)[0], lattice, a.size(), groups);
  BucketCounts buckets;
  for (LevelCounts& worker : *counts) buckets.push_back(std::move(worker.bucket));
  parts = place(
      a, b, b,
      [&](double va, double vb) {
        return Record{ordered_bits(vb), group_of[lattice.known_level(va)]};
      },
      top, std::move(buckets), records, workers);
  return true;
}

// ---- a's groups otherwise: sorting ----

// Sorts each part [bounds[k], bounds[k + 1]) of the records by key, the
// parts shared by the workers (the next unsorted part to the first free).
void sort_parts_by_key(Record* records, const std::vector<std::size_t>& bounds, int workers) {
  std::atomic<std::size_t> next{0};
  const std::size_t parts = bounds.size() - 1;
  parallel_for(workers, workers, [&](int, int) {
    RecordSorter<false> sorter(kSortCapacity);
    for (std::size_t k = next++; k < parts; k = next++) {
      sorter.sort(records + bounds[k], bounds[k + 1] - bounds[k]);
    }
  });
}

// a's groups from records sorted by a's key: one per run of equal keys.
// Rewrites each record as (b's key, a's group).
void groups_from_sorted(Record* records, std::size_t n, GroundGroups& groups) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += i == 0 || records[i].key != records[i - 1].key;
  groups.value.assign(count, 0.0);
  groups.starts = GroupStarts(n, count);
  std::size_t group = 0;
  std::uint64_t previous = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t key = records[i].key;
    if (i == 0 || key != previous) {
      groups.starts.set(i);
      groups.value[group++] = value_of_bits(key);
    }
    previous = key;
    records[i] = Record{records[i].tie, group - 1};
  }
}

// Any other a: the records (a's key, b's key) are scattered into the
// buckets of a's values and sorted by a's key, giving a's groups; then,
// rewritten as (b's key, a's group), split in place into the buckets of b's
// values, whose bounds go to `parts`.
void rank_by_sorting(const ChannelWindow& a, const ChannelWindow& b, Record* records,
                     GroundGroups& groups, std::vector<std::size_t>& parts, int workers) {
  const std::size_t n = a.size();
  const TopBuckets a_top = top_buckets(a);
  const std::vector<std::size_t> a_parts = place(
      a, b, a,
      [](double va, double vb) {
        return Record{ordered_bits(va), ordered_bits(vb)};
      },
      a_top, count_buckets(a, a_top, workers), records, workers);
  sort_parts_by_key(records, a_parts, workers);
  groups_from_sorted(records, n, groups);
  parts = partition_by_key(records, n, top_buckets(b));
}

// ---- b's sort and a's group means ----

// Walks a's groups along b's sorted records, a stretch of ranks at a time
// in rank order: mid_i = (a_(i) + b_(i)) / 2, the mean of the two i-th
// smallest values, replaces b's key; mid_i is summed over each group in
// rank order, and B_G, the sum over the group's size, replaces the group's
// value once its last rank is passed. Marks the first rank of each run of
// equal b values (kRunStart).
class GroupMeans {
 public:
  // From rank `first`, a group's first rank; `previous_key`: b's key at the
  // rank before it (any key of an earlier part will do).
  GroupMeans(GroundGroups& groups, std::size_t first, std::uint64_t previous_key)
      : groups_(groups),
        group_(groups.starts.count_before(first)),
        begin_(first),
        end_(groups.starts.next(first + 1)),
        a_value_(group_ < groups.value.size() ? groups.value[group_] : 0.0),
        previous_(previous_key) {}

  void take(Record* records, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end;) {
      const std::size_t stop = std::min(end, end_);
      // Locals, not members: the stores to the records could alias these.
      std::uint64_t previous = previous_;
      double sum = sum_;
      const double a_value = a_value_;
      for (; i < stop; ++i) {
        const std::uint64_t key = records[i].key;
        const double mid = 0.5 * (a_value + value_of_bits(key));
        records[i].key = as_bits(mid);
        if (i == 0 || key != previous) records[i].tie |= kRunStart;
        previous = key;
        sum += mid;
      }
      previous_ = previous;
      sum_ = sum;
      if (i == end_) next_group();
    }
  }

 private:
  void next_group() {
    groups_.value[group_] = sum_ / static_cast<double>(end_ - begin_);
    sum_ = 0.0;
    begin_ = end_;
    end_ = groups_.starts.next(end_ + 1);
    if (++group_ < groups_.value.size()) a_value_ = groups_.value[group_];
  }

  GroundGroups& groups_;
  std::size_t group_;  // the group of ranks [begin_, end_)
  std::size_t begin_;
  std::size_t end_;
  double a_value_;
  double sum_ = 0.0;
  std::uint64_t previous_;
};

// The part holding rank r (the last of equal bounds: empty parts skipped).
std::size_t part_of(const std::vector<std::size_t>& bounds, std::size_t r) {
  return static_cast<std::size_t>(std::upper_bound(bounds.begin(), bounds.end(), r) -
                                  bounds.begin()) -
         1;
}

// Sorts the parts of the records overlapping ranks [begin, end), but
// `presorted`, and takes a's group means along them while they are in
// cache.
void sort_and_take_means(Record* records, const std::vector<std::size_t>& bounds,
                         std::size_t presorted, std::size_t begin, std::size_t end,
                         GroupMeans& means) {
  RecordSorter<true> sorter(kSortCapacity);
  for (std::size_t k = part_of(bounds, begin); k + 1 < bounds.size() && bounds[k] < end; ++k) {
    if (k != presorted) sorter.sort(records + bounds[k], bounds[k + 1] - bounds[k]);
    means.take(records, std::max(bounds[k], begin), std::min(bounds[k + 1], end));
  }
}

// Sorts the parts [bounds[k], bounds[k + 1]) of b's records and takes a's
// group means. With two workers the ranks are split at the start of a's
// group nearest the middle (a group's sum stays on one worker): the part
// holding it is sorted first, then each worker sorts the other parts of
// its ranks and takes their means.
void sort_all_and_take_means(Record* records, const std::vector<std::size_t>& bounds,
                             GroundGroups& groups, int workers) {
  const std::size_t n = bounds.back();
  std::vector<std::size_t> split = {0, n};
  std::size_t presorted = bounds.size();  // none
  if (workers > 1 && groups.starts.next(n / 2) < n) {
    split = {0, groups.starts.next(n / 2), n};
    const std::size_t k = part_of(bounds, split[1]);
    if (bounds[k] < split[1]) {
      RecordSorter<true>(kSortCapacity).sort(records + bounds[k], bounds[k + 1] - bounds[k]);
      presorted = k;
    }
  }
  std::vector<GroupMeans> means;
  for (std::size_t w = 0; w + 1 < split.size(); ++w) {
    means.emplace_back(groups, split[w], split[w] > 0 ? records[split[w] - 1].key : 0);
  }
  parallel_for(static_cast<int>(means.size()), workers, [&](int begin, int end) {
    for (auto w = static_cast<std::size_t>(begin); w < static_cast<std::size_t>(end); ++w) {
      sort_and_take_means(records, bounds, presorted, split[w], split[w + 1], means[w]);
    }
  });
}

// ---- The sums ----

// One past the last rank of b's run of equal values starting at rank s.
std::size_t run_end(const Record* records, std::size_t s, std::size_t n) {
  ++s;
  while (s < n && (records[s].tie & kRunStart) == 0) ++s;
  return s;
}

// B_H: the mean of mid_i over b's run [s, e), summed in rank order.
double run_mean(const Record* records, std::size_t s, std::size_t e) {
  double sum = 0.0;
  for (std::size_t i = s; i < e; ++i) sum += as_double(records[i].key);
  return sum / static_cast<double>(e - s);
}

// m2_H = sum_{i in H} (mid_i - B_H)^2 over b's run [s, e), in rank order.
double run_spread(const Record* records, std::size_t s, std::size_t e, double mean) {
  double m2 = 0.0;
  for (std::size_t i = s; i < e; ++i) {
    const double d = as_double(records[i].key) - mean;
    m2 += d * d;
  }
  return m2;
}

// m2_sum + sum_H m2_H over b's runs of more than one rank, in rank order
// (m2 of a run of one is 0).
double b_spread(const Record* records, std::size_t n, double m2_sum) {
  for (std::size_t s = 0, e = 0; s < n; s = e) {
    e = run_end(records, s, n);
    if (e - s > 1) m2_sum += run_spread(records, s, e, run_mean(records, s, e));
  }
  return m2_sum;
}

// What a pass over the ranks sums: sum_G m2_G over a's groups in rank
// order (m2_G = sum_{i in G} (mid_i - B_G)^2, in rank order), the count of
// b's runs of more than one rank (their m2 go to a list), and sum_p (B_G -
// B_H)^2 over b's ranks in order (B_G by a's group, kept in each record's
// tie).
struct RankSums {
  double a_m2 = 0.0;
  std::size_t b_runs = 0;
  double cross = 0.0;
};

// The spreads (kSpread: a's sum, and the m2 of b's runs of more than one
// rank in rank order into `b_m2`, as long as there is room) and the cross
// sum (kCross), in one pass. Written without calls, so that the running
// sums stay in registers.
template <bool kSpread, bool kCross>
RankSums sum_ranks(const Record* records, std::size_t n, const GroundGroups& groups, double* b_m2,
                   std::size_t room) {
  double a_sum = 0.0;
  double a_m2 = 0.0;
  double cross = 0.0;
  std::size_t group = 0;
  std::size_t group_end = groups.starts.next(1);
  double a_mean = groups.value[0];
  std::size_t runs = 0;
  for (std::size_t s = 0, e = 0; s < n; s = e) {
    e = run_end(records, s, n);
    const double b_mean = e - s == 1 ? as_double(records[s].key) : run_mean(records, s, e);
    for (std::size_t i = s; i < e; ++i) {
      if (kSpread && i == group_end) {
        a_sum += a_m2;
        a_m2 = 0.0;
        a_mean = groups.value[++group];
        group_end = groups.starts.next(i + 1);
      }
      const double d_a = as_double(records[i].key) - a_mean;
      if (kSpread) a_m2 += d_a * d_a;
      const double d = groups.value[records[i].tie & ~kRunStart] - b_mean;
      if (kCross) cross += d * d;
    }
    if (kSpread && e - s > 1 && runs++ < room) {
      b_m2[runs - 1] = run_spread(records, s, e, b_mean);
    }
  }
  return {a_sum + a_m2, runs, cross};
}

// The channel's sum: sum_G m2_G + sum_H m2_H (one chain: a's groups, then
// b's runs of more than one rank), plus the cross sum. With two workers,
// one takes the spreads and the other the cross sum, each in its order.
// b's m2 are kept for up to kListedRuns runs (512 KiB, untouched unless b
// has ties); beyond, b_spread sums them again.
constexpr std::size_t kListedRuns = 65536;

double sum_all_ranks(const Record* records, std::size_t n, const GroundGroups& groups,
                     int workers) {
  const std::size_t room = std::min(n, kListedRuns);
  const auto b_m2 = std::make_unique_for_overwrite<double[]>(room);
  RankSums sums;
  if (workers > 1) {
    parallel_for(2, 2, [&](int begin, int end) {
      for (int task = begin; task < end; ++task) {
        if (task == 0) {
          sums.cross = sum_ranks<false, true>(records, n, groups, nullptr, 0).cross;
        } else {
          const RankSums spreads = sum_ranks<true, false>(records, n, groups, b_m2.get(), room);
          sums.a_m2 = spreads.a_m2;
          sums.b_runs = spreads.b_runs;
        }
      }
    });
  } else {
    sums = sum_ranks<true, true>(records, n, groups, b_m2.get(), room);
  }
  if (sums.b_runs > room) return b_spread(records, n, sums.a_m2) + sums.cross;
  double m2_sum = sums.a_m2;
  for (std::size_t k = 0; k < sums.b_runs; ++k) m2_sum += b_m2[k];
  return m2_sum + sums.cross;
}

}  // namespace

double expected_midway_sum(const ChannelWindow& a, const ChannelWindow& b, Record* records,
                           int workers) {
  const std::size_t n = a.size();
  if (n == 0) return 0.0;
  workers = workers > 1 ? 2 : 1;
  GroundGroups groups;
  std::vector<std::size_t> parts;
  const TopBuckets b_top = top_buckets(b);
  if (!rank_on(Lattice<false>(), a, b, b_top, records, groups, parts, workers) &&
      !rank_on(Lattice<true>(), a, b, b_top, records, groups, parts, workers)) {
    rank_by_sorting(a, b, records, groups, parts, workers);
  }
  sort_all_and_take_means(records, parts, groups, workers);
  return sum_all_ranks(records, n, groups, workers);
}

}  // namespace fss::midway
