// Tests of the record sorting behind RMSE_CI (src/pipeline/record_sort.h):
// the order-preserving bits, the bucket maps (monotone, ends in the first
// and last bucket, whatever the values), the top-level buckets and the
// bucket sort (the order of std::sort on every kind of key distribution,
// with its in-place splits and its std::sort fallback reached).

#include "pipeline/record_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace fss::midway {
namespace {

// Values of one kind, as their ordered bits.
std::vector<std::uint64_t> keys_of(const std::vector<double>& values) {
  std::vector<std::uint64_t> keys;
  keys.reserve(values.size());
  for (const double v : values) keys.push_back(ordered_bits(v));
  return keys;
}

// Kinds of value sets, each with n values from `rng`.
std::vector<std::pair<std::string, std::vector<double>>> value_sets(std::size_t n,
                                                                    std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::pair<std::string, std::vector<double>>> sets;
  auto make = [&](const std::string& name, const std::function<double()>& value) {
    std::vector<double> v(n);
    for (double& x : v) x = value();
    sets.emplace_back(name, v);
  };
  make("gray", [&] { return -30.0 + 320.0 * unit(rng); });
  make("integers", [&] { return std::round(255.0 * unit(rng)); });
  make("denormals", [&] { return static_cast<double>(rng() % 4096) * 4.9e-324; });
  make("signed zeros and denormals", [&] {
    const double values[] = {-0.0, 0.0, 4.9e-324, -4.9e-324, 1e-310};
    return values[rng() % 5];
  });
  make("huge", [&] { return (unit(rng) < 0.5 ? -1.0 : 1.0) * 1e300 * unit(rng); });
  make("overflowing range", [&] {
    const double values[] = {-1.7e308, 1.7e308, 0.0, 1.0};
    return values[rng() % 4];
  });
  make("ulps", [&] { return 1.0 + static_cast<double>(rng() % 8) * 0x1p-52; });
  make("one outlier", [&] { return rng() % 1000 == 0 ? 1e150 : 100.0 * unit(rng); });
  make("every binade", [&] {
    double v = std::bit_cast<double>(rng());
    while (std::isnan(v)) v = std::bit_cast<double>(rng());
    return v;
  });
  make("geometric", [&] { return std::ldexp(1.0, static_cast<int>(rng() % 2000) - 1000); });
  make("one value", [] { return 42.0; });
  return sets;
}

TEST(OrderedBits, OrderTheValuesAndComeBack) {
  const std::vector<double> sorted = {-std::numeric_limits<double>::infinity(),
                                      -1e300,
                                      -1.0,
                                      -4.9e-324,
                                      0.0,
                                      4.9e-324,
                                      2.2250738585072014e-308,
                                      1.0,
                                      1.0 + 0x1p-52,
                                      1e300,
                                      std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i + 1 < sorted.size(); ++i) {
    EXPECT_LT(ordered_bits(sorted[i]), ordered_bits(sorted[i + 1])) << sorted[i];
  }
  for (const double v : sorted) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(value_of_bits(ordered_bits(v))),
              std::bit_cast<std::uint64_t>(v));
  }
  EXPECT_EQ(ordered_bits(-0.0), ordered_bits(0.0));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(value_of_bits(ordered_bits(-0.0))),
            std::bit_cast<std::uint64_t>(0.0));
}

// Monotone, lowest key to bucket 0, highest to the last, at most the
// buckets asked for (twice as many for a map in the bits).
void expect_good_map(const BucketMap& map, std::vector<std::uint64_t> keys, std::size_t buckets,
                     const std::string& name) {
  std::sort(keys.begin(), keys.end());
  ASSERT_LE(map.count(), 2 * buckets) << name;
  EXPECT_EQ(map(keys.front()), 0u) << name;
  EXPECT_EQ(map(keys.back()), map.count() - 1) << name;
  if (keys.front() != keys.back()) EXPECT_GT(map.count(), 1u) << name;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    ASSERT_LE(map(keys[i]), map(keys[i + 1])) << name << " at " << i;
    ASSERT_LT(map(keys[i + 1]), map.count()) << name;
  }
}

TEST(BucketMap, IsMonotoneAndSpansItsBucketsForEveryKindOfValue) {
  std::mt19937_64 rng(1);
  for (const std::size_t buckets : {2u, 3u, 100u, 4096u}) {
    for (const auto& [name, values] : value_sets(5000, rng)) {
      const std::vector<std::uint64_t> keys = keys_of(values);
      const auto [low, high] = std::minmax_element(keys.begin(), keys.end());
      expect_good_map(BucketMap::of_values(*low, *high, buckets), keys, buckets, name);
      expect_good_map(BucketMap::of_integers(*low, *high, buckets), keys, buckets, name);
      // the same by value, without the bits (top-level buckets read values)
      const BucketMap map = BucketMap::of_values(*low, *high, buckets);
      for (const double v : values) ASSERT_EQ(map.of_value_bits(v), map(ordered_bits(v))) << name;
    }
  }
}

TEST(BucketMap, SplitsKeysAsFarApartAsTheyCome) {
  const std::uint64_t top = ~std::uint64_t{0};
  for (const std::size_t buckets : {1u, 2u, 4096u}) {
    const BucketMap map = BucketMap::of_integers(0, top, buckets);
    EXPECT_EQ(map(0), 0u);
    EXPECT_EQ(map(top), map.count() - 1);
    EXPECT_GE(map.count(), 2u);
  }
  // Linear in the value: a gray range is cut into equal widths.
  const BucketMap map = BucketMap::of_values(ordered_bits(0.0), ordered_bits(256.0), 256);
  EXPECT_EQ(map.count(), 256u);
  EXPECT_EQ(map(ordered_bits(100.5)), 100u);
  EXPECT_EQ(map(ordered_bits(-0.0)), 0u);
}

TEST(TopBuckets, PutExtremesAsideAndStayMonotone) {
  std::mt19937_64 rng(2);
  for (const auto& [name, values] : value_sets(20000, rng)) {
    std::vector<std::uint64_t> sample;
    for (std::size_t i = 0; i < values.size(); i += 7) sample.push_back(ordered_bits(values[i]));
    const TopBuckets top(sample, 64);
    std::vector<double> sorted = values;
    sorted.push_back(-0.0);
    sorted.push_back(-std::numeric_limits<double>::infinity());  // beyond the sample
    sorted.push_back(std::numeric_limits<double>::infinity());
    std::sort(sorted.begin(), sorted.end(),
              [](double x, double y) { return ordered_bits(x) < ordered_bits(y); });
    EXPECT_EQ(top.of_value(sorted.front()), 0u) << name;
    EXPECT_EQ(top.of_value(sorted.back()), top.count() - 1) << name;
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      ASSERT_EQ(top.of_value(sorted[i]), top.of_key(ordered_bits(sorted[i]))) << name;
      if (i > 0) ASSERT_LE(top.of_value(sorted[i - 1]), top.of_value(sorted[i])) << name;
    }
  }
  // One pixel at 1e150 does not crowd the others into one bucket.
  std::vector<std::uint64_t> sample;
  sample.reserve(10000);
  for (int i = 0; i < 10000; ++i) sample.push_back(ordered_bits(i * 0.0255));
  sample[5000] = ordered_bits(1e150);
  const TopBuckets top(sample, 102);
  EXPECT_EQ(top.of_value(1e150), top.count() - 1);
  EXPECT_EQ(top.of_value(0.0), 0u);
  EXPECT_GT(top.of_value(127.5), top.of_value(25.5) + 30);
}

// Records of keys from `values` and ties in [0, ties).
std::vector<Record> records_of(const std::vector<double>& values, std::uint64_t ties,
                               std::mt19937_64& rng) {
  std::vector<Record> records;
  records.reserve(values.size());
  for (const double v : values) records.push_back(Record{ordered_bits(v), rng() % ties});
  return records;
}

bool record_less(const Record& x, const Record& y) {
  return x.key < y.key || (x.key == y.key && x.tie < y.tie);
}

bool same_records(const std::vector<Record>& x, const std::vector<Record>& y) {
  return std::equal(x.begin(), x.end(), y.begin(), y.end(), [](const Record& p, const Record& q) {
    return p.key == q.key && p.tie == q.tie;
  });
}

// Sizes below the insertion threshold, in cache (the buffer holds 4096 here),
// and above it (split in place); ties from one value to 2^63.
TEST(RecordSorter, SortsByKeyThenTieLikeStdSort) {
  std::mt19937_64 rng(3);
  RecordSorter<true> sorter(4096);
  for (const std::size_t n : {0u, 1u, 2u, 17u, 1000u, 4096u, 30000u}) {
    for (const auto& [name, values] : value_sets(n, rng)) {
      for (const std::uint64_t ties :
           {std::uint64_t{1}, std::uint64_t{7}, std::uint64_t{1} << 63}) {
        std::vector<Record> records = records_of(values, ties, rng);
        std::vector<Record> expected = records;
        std::sort(expected.begin(), expected.end(), record_less);
        sorter.sort(records.data(), records.size());
        EXPECT_TRUE(same_records(records, expected)) << name << ", n " << n << ", ties " << ties;
      }
    }
  }
}

// Many equal keys (b's ties): a bucket larger than the buffer, sorted by
// tie in place; and a range of all-equal records.
TEST(RecordSorter, SortsLargeRunsOfEqualKeysByTie) {
  std::mt19937_64 rng(4);
  RecordSorter<true> sorter(1024);
  std::vector<Record> records;
  records.reserve(55000);
  for (int i = 0; i < 50000; ++i) {
    records.push_back(
        Record{ordered_bits(i % 3 == 0 ? 17.0 : static_cast<double>(i % 5)), rng() % 300});
  }
  for (int i = 0; i < 5000; ++i) records.push_back(Record{ordered_bits(-1.0), 9});
  std::shuffle(records.begin(), records.end(), rng);
  std::vector<Record> expected = records;
  std::sort(expected.begin(), expected.end(), record_less);
  sorter.sort(records.data(), records.size());
  EXPECT_TRUE(same_records(records, expected));
}

TEST(RecordSorter, ByKeyAloneLeavesTiesInAnyOrder) {
  std::mt19937_64 rng(5);
  RecordSorter<false> sorter(2048);
  for (const auto& [name, values] : value_sets(20000, rng)) {
    std::vector<Record> records = records_of(values, 1000, rng);
    std::vector<Record> expected = records;
    std::sort(expected.begin(), expected.end(), record_less);
    sorter.sort(records.data(), records.size());
    EXPECT_TRUE(std::is_sorted(records.begin(), records.end(),
                               [](const Record& x, const Record& y) { return x.key < y.key; }))
        << name;
    std::sort(records.begin(), records.end(), record_less);  // the same records
    EXPECT_TRUE(same_records(records, expected)) << name;
  }
}

TEST(PartitionByKey, PutsIncreasingKeyRangesInTheParts) {
  std::mt19937_64 rng(6);
  for (const auto& [name, values] : value_sets(30000, rng)) {
    std::vector<Record> records = records_of(values, 5, rng);
    std::vector<std::uint64_t> sample;
    for (std::size_t i = 0; i < records.size(); i += 11) sample.push_back(records[i].key);
    const TopBuckets top(sample, 40);
    const std::vector<std::size_t> bounds = partition_by_key(records.data(), records.size(), top);
    ASSERT_EQ(bounds.size(), top.count() + 1) << name;
    ASSERT_EQ(bounds.back(), records.size()) << name;
    std::uint64_t previous_high = 0;
    bool any = false;
    for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
      if (bounds[k] == bounds[k + 1]) continue;
      const auto [low, high] =
          std::minmax_element(records.begin() + static_cast<std::ptrdiff_t>(bounds[k]),
                              records.begin() + static_cast<std::ptrdiff_t>(bounds[k + 1]),
                              [](const Record& x, const Record& y) { return x.key < y.key; });
      if (any) ASSERT_LT(previous_high, low->key) << name << ", part " << k;
      for (std::size_t i = bounds[k]; i < bounds[k + 1]; ++i)
        ASSERT_EQ(top.of_key(records[i].key), k);
      previous_high = high->key;
      any = true;
    }
  }
}

}  // namespace
}  // namespace fss::midway
