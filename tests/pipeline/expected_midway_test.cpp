// Tests of the tie expectation of one channel (src/pipeline/expected_midway.h)
// with one and two workers on windows of every size: rmse_contrast_invariant
// gives small windows one thread (kParallelRmseCiPixels), so the two-worker
// paths (the ranks split at one of a's group starts, a bucket sorted first,
// the sums split by kind) are reached here on all of the corpus.

#include "pipeline/expected_midway.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "pipeline/rmse_ci_corpus.h"

namespace fss::midway {
namespace {

ChannelWindow window_of(const Image& image, int c, int first, int end) {
  ChannelWindow w;
  w.first = image.row(c, 0) + first;
  w.stride = static_cast<std::size_t>(image.width);
  w.width = static_cast<std::uint32_t>(end - first);
  w.height = static_cast<std::uint32_t>(image.height);
  return w;
}

TEST(ExpectedMidwaySum, TwoWorkersGiveTheBitsOfOneOnTheCorpus) {
  std::size_t checked = 0;
  test::for_each_corpus_case([&](const test::CorpusCase& k) {
    const std::size_t n = static_cast<std::size_t>(k.end - k.first) * k.b.height;
    RecordBuffer records(n);
    for (int c = 0; c < k.b.channels; ++c) {
      const ChannelWindow a = window_of(k.a, c, k.first + k.a_offset, k.end + k.a_offset);
      const ChannelWindow b = window_of(k.b, c, k.first, k.end);
      const double one = expected_midway_sum(a, b, records.data(), 1);
      const double two = expected_midway_sum(a, b, records.data(), 2);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(two), std::bit_cast<std::uint64_t>(one))
          << k.name << ", channel " << c << ": " << one << " and " << two;
      ++checked;
    }
  });
  EXPECT_GT(checked, 700u);
}

// The channel's sum against the plain reference's, bit for bit, with two
// workers on windows of a few hundred pixels.
TEST(ExpectedMidwaySum, TwoWorkersGiveTheReferenceSumOnSmallWindows) {
  for (const std::string& a_kind : test::corpus_a_kinds()) {
    for (const std::string& b_kind : test::corpus_b_kinds()) {
      const test::CorpusCase k = test::make_corpus_case(a_kind, b_kind, 23, 19, 1);
      std::vector<double> av;
      std::vector<double> bv;
      for (int y = 0; y < k.b.height; ++y) {
        for (int x = k.first; x < k.end; ++x) {
          av.push_back(k.a.at(0, y, x + k.a_offset));
          bv.push_back(k.b.at(0, y, x));
        }
      }
      RecordBuffer records(av.size());
      const double sum =
          expected_midway_sum(window_of(k.a, 0, k.first + k.a_offset, k.end + k.a_offset),
                              window_of(k.b, 0, k.first, k.end), records.data(), 2);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(sum),
                std::bit_cast<std::uint64_t>(test::reference_channel_sum(av, bv)))
          << k.name;
    }
  }
}

// b's values in pairs (every value twice) and a's groups of a few hundred
// pixels: where the two workers split the ranks (at one of a's group
// starts, inside a bucket), b's run often straddles the split, so the
// bucket there must be sorted before either worker reads it, and the run
// must not be cut in two.
TEST(ExpectedMidwaySum, TwoWorkersKeepARunAcrossTheirSplit) {
  for (int seed = 0; seed < 8; ++seed) {
    Image a(300, 200, 1);
    Image b(300, 200, 1);
    test::CorpusRandom random(static_cast<std::uint64_t>(seed));
    for (std::size_t i = 0; i < a.data.size(); ++i) {
      a.data[i] = static_cast<double>(random.next() % 200);
      const std::size_t pair = (i * 7919 + static_cast<std::size_t>(seed)) % 60000 / 2;
      b.data[i] = static_cast<double>(pair);
    }
    std::vector<double> av(a.data.begin(), a.data.end());
    std::vector<double> bv(b.data.begin(), b.data.end());
    RecordBuffer records(av.size());
    const double sum =
        expected_midway_sum(window_of(a, 0, 0, 300), window_of(b, 0, 0, 300), records.data(), 2);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(sum),
              std::bit_cast<std::uint64_t>(test::reference_channel_sum(av, bv)))
        << "seed " << seed;
  }
}

}  // namespace
}  // namespace fss::midway
