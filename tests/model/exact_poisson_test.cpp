// The exact Poisson sampler of the aggregated noise (src/model/exact_poisson.h,
// docs/method.md §6c): its distribution at means on both sides of the switch
// from inversion to transformed rejection, against the exact probabilities.
#include "model/exact_poisson.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "model/bounded_log.h"
#include "support/test_util.h"

namespace fss {
namespace {

// P(X = k), X ~ Poisson(mean), in long double from lgamma.
long double exact_pmf(long double k, long double mean) {
  return std::exp(-mean + k * std::log(mean) - std::lgamma(k + 1.0L));
}

struct SampleStatistics {
  double mean_z = 0.0;      // (sample mean - mean) / its standard error
  double variance_z = 0.0;  // (sample variance - mean) / its standard error
  double chi_square_z = 0.0;
  int bins = 0;
};

// Draws n values and compares them with Poisson(mean): the sample mean and
// variance against theirs (Var of the sample variance (mu_4 - sigma^4) / n =
// (mean + 2 mean^2) / n), and Pearson's chi-square over bins of consecutive
// values each expected at least 20 times (the tails in the end bins), as a
// normal deviate by Wilson and Hilferty's cube root,
//   z = ((chi^2 / df)^(1/3) - (1 - 2 / (9 df))) / sqrt(2 / (9 df)),
// whose tail matches chi^2's even for the 2 degrees of freedom of a small
// mean (where (chi^2 - df) / sqrt(2 df) > 3 has probability 1.8 %, not 0.13 %).
SampleStatistics compare_with_poisson(double mean, int n, const std::function<double()>& draw) {
  std::vector<long long> counts;
  long double sum = 0.0L, sum_sq = 0.0L;
  for (int i = 0; i < n; ++i) {
    const double k = draw();
    EXPECT_EQ(k, std::floor(k));
    EXPECT_GE(k, 0.0);
    const auto index = static_cast<std::size_t>(k);
    if (index >= counts.size()) counts.resize(index + 1, 0);
    ++counts[index];
    sum += k;
    sum_sq += static_cast<long double>(k) * k;
  }
  SampleStatistics s;
  const long double sample_mean = sum / n;
  const long double sample_variance = (sum_sq - n * sample_mean * sample_mean) / (n - 1);
  s.mean_z = static_cast<double>((sample_mean - mean) / std::sqrt(mean / n));
  s.variance_z =
      static_cast<double>((sample_variance - mean) / std::sqrt((mean + 2.0 * mean * mean) / n));
  // Bins [start, k] closed when their expected count reaches 20, from 12
  // standard deviations below the mean (P(X below) < 1e-30: the values there
  // counted into the first bin) to 12 above.
  const double bottom = std::max(0.0, std::floor(mean - 12.0 * std::sqrt(mean) - 40.0));
  const double top = mean + 12.0 * std::sqrt(mean) + 40.0;
  long double chi_square = 0.0L, expected = 0.0L, cumulative = 0.0L;
  long long observed = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(bottom) && i < counts.size(); ++i) {
    observed += counts[i];
  }
  for (long double k = bottom; k <= top; k += 1.0L) {
    const long double p = exact_pmf(k, mean);
    cumulative += p;
    expected += n * p;
    const auto index = static_cast<std::size_t>(k);
    observed += index < counts.size() ? counts[index] : 0;
    if (expected >= 20.0L && n * (1.0L - cumulative) >= 20.0L) {
      chi_square += (observed - expected) * (observed - expected) / expected;
      ++s.bins;
      expected = 0.0L;
      observed = 0;
    }
  }
  // The last bin holds the rest of the distribution.
  long long rest = 0;
  for (std::size_t i = static_cast<std::size_t>(top) + 1; i < counts.size(); ++i) rest += counts[i];
  expected += n * std::max(0.0L, 1.0L - cumulative);
  observed += rest;
  chi_square += (observed - expected) * (observed - expected) / expected;
  ++s.bins;
  const double df = s.bins - 1;
  const double spread = 2.0 / (9.0 * df);
  s.chi_square_z =
      (std::cbrt(static_cast<double>(chi_square) / df) - (1.0 - spread)) / std::sqrt(spread);
  return s;
}

class ExactPoissonDistribution : public ::testing::TestWithParam<double> {};

// Mean, variance and probabilities within 3 standard errors, at several seeds.
TEST_P(ExactPoissonDistribution, IsPoisson) {
  const double mean = GetParam();
  const int n = test::kAddressSanitizer ? 20000 : 400000;
  for (const std::uint64_t seed : {1, 2, 3}) {
    // Each mean its own streams (the mean's bits as the channel coordinate).
    RandomStream stream(seed, std::bit_cast<std::uint64_t>(mean), 0, 0,
                        static_cast<std::uint64_t>(NoiseLane::kGroupPoisson));
    const SampleStatistics s =
        compare_with_poisson(mean, n, [&] { return exact_poisson_variate(mean, stream); });
    EXPECT_LT(std::abs(s.mean_z), 3.0) << "mean " << mean << " seed " << seed;
    EXPECT_LT(std::abs(s.variance_z), 3.0) << "mean " << mean << " seed " << seed;
    EXPECT_LT(std::abs(s.chi_square_z), 3.0)
        << "mean " << mean << " seed " << seed << " over " << s.bins << " bins";
    // The row sampler, which orders its uniforms otherwise, over a row of n pixels.
    const std::vector<double> means(static_cast<std::size_t>(n), mean);
    std::vector<double> row(means.size(), 0.0);
    add_exact_poisson_row(means, stream, 1.0, row);
    std::size_t next = 0;
    const SampleStatistics r = compare_with_poisson(mean, n, [&] { return row[next++]; });
    EXPECT_LT(std::abs(r.mean_z), 3.0) << "row, mean " << mean << " seed " << seed;
    EXPECT_LT(std::abs(r.variance_z), 3.0) << "row, mean " << mean << " seed " << seed;
    EXPECT_LT(std::abs(r.chi_square_z), 3.0) << "row, mean " << mean << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Means, ExactPoissonDistribution,
                         ::testing::Values(0.1, 1.0, 5.0, 9.99, 10.0, 10.5, 50.0, 1e3, 1e6),
                         [](const auto& info) {
                           std::string name = std::to_string(info.param);
                           for (char& c : name) c = c == '.' ? '_' : c;
                           return name;
                         });

// The test has power: at mean 10 the per-frame sampler's rounded normal
// (skewness 0, Poisson's 0.32) is far outside it.
TEST(ExactPoisson, TheComparisonRejectsARoundedNormal) {
  const int n = test::kAddressSanitizer ? 20000 : 400000;
  RandomStream stream(5, 0, 0, 0, 0);
  const double mean = 10.0;
  const SampleStatistics s = compare_with_poisson(mean, n, [&] {
    return std::max(0.0, std::nearbyint(mean + std::sqrt(mean) * stream.standard_normal()));
  });
  EXPECT_GT(s.chi_square_z, 10.0);
}

TEST(ExactPoisson, LogProbabilityIsExactOnBothSidesOfTheTable) {
  for (const double mean : {10.0, 63.5, 1e3, 1e6, 1e12}) {
    const double sd = std::sqrt(mean);
    for (const double offset : {-5.0, -1.0, 0.0, 0.5, 1.0, 3.0, 8.0}) {
      const double k = std::max(0.0, std::floor(mean + offset * sd));
      const long double exact = -static_cast<long double>(mean) +
                                k * std::log(static_cast<long double>(mean)) -
                                std::lgamma(static_cast<long double>(k) + 1.0L);
      // Within 1e-13 of the log-probability's scale 1 + |ln P|; long double's
      // own terms lose about 1e-19 |k ln mean|.
      const double tolerance = 1e-13 * (1.0 + std::abs(static_cast<double>(exact))) +
                               4e-19 * k * std::abs(std::log(mean));
      EXPECT_NEAR(poisson_log_pmf(k, mean), static_cast<double>(exact), tolerance)
          << "k " << k << " mean " << mean;
    }
  }
  for (const double k : {0.0, 1.0, 63.0, 64.0, 65.0}) {
    EXPECT_NEAR(poisson_log_pmf(k, 64.0),
                static_cast<double>(-64.0L + k * std::log(64.0L) - std::lgamma(k + 1.0L)), 1e-12)
        << "k " << k;
  }
}

TEST(ExactPoisson, EdgeMeansDrawNothing) {
  RandomStream stream(9, 0, 0, 0, 0);
  const RandomStream before = stream;
  EXPECT_EQ(exact_poisson_variate(0.0, stream), 0.0);
  EXPECT_EQ(exact_poisson_variate(-3.0, stream), 0.0);
  EXPECT_EQ(exact_poisson_variate(std::numeric_limits<double>::quiet_NaN(), stream), 0.0);
  EXPECT_EQ(exact_poisson_variate(std::numeric_limits<double>::infinity(), stream),
            std::numeric_limits<double>::infinity());
  RandomStream copy = before;
  EXPECT_EQ(stream.next(), copy.next());  // no draw above
  // A tiny mean is almost always 0, a huge one finite and near it.
  EXPECT_EQ(exact_poisson_variate(1e-300, stream), 0.0);
  const double huge = exact_poisson_variate(1e300, stream);
  EXPECT_NEAR(huge / 1e300, 1.0, 1e-12);
}

// A row of mixed means (both algorithms, zeros, a block boundary inside):
// scaled and added to `out`, each class of pixels with its mean within 3
// standard errors; the same stream gives the same row.
TEST(ExactPoisson, RowOfMixedMeans) {
  const std::vector<double> pattern = {0.0, 0.4, 9.99, 10.0, 2500.0, 77.0, 3.0};
  const std::size_t repeats = test::kAddressSanitizer ? 3000 : 30000;
  std::vector<double> means;
  for (std::size_t r = 0; r < repeats; ++r)
    means.insert(means.end(), pattern.begin(), pattern.end());
  for (const std::uint64_t seed : {11, 12}) {
    std::vector<double> out(means.size(), 1.0);
    RandomStream stream(seed, 0, 0, 0, 5);
    add_exact_poisson_row(means, stream, 0.5, out);
    std::vector<double> again(means.size(), 1.0);
    RandomStream same(seed, 0, 0, 0, 5);
    add_exact_poisson_row(means, same, 0.5, again);
    EXPECT_TRUE(out == again);
    for (std::size_t j = 0; j < pattern.size(); ++j) {
      double sum = 0.0;
      for (std::size_t r = 0; r < repeats; ++r) sum += (out[r * pattern.size() + j] - 1.0) / 0.5;
      const double n = static_cast<double>(repeats);
      if (pattern[j] == 0.0) {
        EXPECT_EQ(sum, 0.0);
        continue;
      }
      EXPECT_LT(std::abs(sum / n - pattern[j]) / std::sqrt(pattern[j] / n), 3.0)
          << "mean " << pattern[j] << " seed " << seed;
    }
  }
}

// The bulk slow test's logarithms within their stated bound, 1e-13 (1 +
// |result|), against long double: arguments log-uniform over the normal
// doubles, powers of two and their neighbours, both sides of sqrt(2) and of
// the switch at |t| = 1/4, and t near -1 and near 0.
TEST(BoundedLog, WithinItsBound) {
  const auto check = [](double got, long double exact, double argument) {
    const long double error = std::abs(static_cast<long double>(got) - exact);
    EXPECT_LE(error, 1e-13L * (1.0L + std::abs(exact))) << "argument " << argument;
  };
  RandomStream pick(5, 0, 0, 0, 0);
  std::vector<double> ys;
  ys.reserve(200000 + 5 * 2046);
  for (int i = 0; i < 200000; ++i) ys.push_back(std::pow(2.0, -1020.0 + 2040.0 * pick.uniform()));
  for (int e = -1022; e <= 1023; ++e) {
    const double p = std::ldexp(1.0, e);
    ys.insert(ys.end(), {p, std::nextafter(p, 0.0), std::nextafter(p, 1e308),
                         p * std::numbers::sqrt2, std::nextafter(p * std::numbers::sqrt2, 0.0)});
  }
  for (const double y : ys) check(bounded_log(y), std::log(static_cast<long double>(y)), y);
  std::vector<double> ts = {0.0,
                            1e-300,
                            -1e-300,
                            1e-17,
                            -1e-17,
                            0.25,
                            -0.25,
                            1e6,
                            1e300,
                            std::nextafter(0.25, 1.0),
                            std::nextafter(-0.25, -1.0),
                            -1.0 + 1e-10,
                            std::nextafter(-1.0, 0.0)};
  for (int i = 0; i < 200000; ++i) ts.push_back(-1.0 + 3.0 * pick.uniform_open_zero());
  for (int i = 0; i < 2000; ++i) ts.push_back(std::pow(10.0, -20.0 + 40.0 * pick.uniform()));
  for (const double t : ts) check(bounded_log1p(t), std::log1p(static_cast<long double>(t)), t);
}

// The first tries left to the slow test, decided in bulk by bounded
// logarithms, decide as the scalar test does: the same bits and the same
// stream position after rows of means from 10^-1 to 10^13 (both sides of the
// log-factorial table, the inversion, overflow-free and huge means, zeros).
TEST(ExactPoisson, BulkSlowTestDecidesAsTheScalarTest) {
  const std::size_t width = test::kAddressSanitizer ? 5000 : 40000;
  for (const std::uint64_t seed : {1, 2, 3, 4}) {
    std::vector<double> means(width);
    RandomStream pick(seed, 9, 9, 9, 9);
    for (double& m : means) m = std::pow(10.0, -1.0 + 14.0 * pick.uniform());
    means[7] = 0.0;
    means[8] = 1e300;
    means[9] = std::numeric_limits<double>::infinity();
    std::vector<double> bulk(width, 0.25), scalar(width, 0.25);
    RandomStream a(seed, 1, 2, 3, 4), b(seed, 1, 2, 3, 4);
    add_exact_poisson_row(means, a, 0.5, bulk);
    add_exact_poisson_row_scalar(means, b, 0.5, scalar);
    for (std::size_t x = 0; x < width; ++x) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(bulk[x]), std::bit_cast<std::uint64_t>(scalar[x]))
          << "pixel " << x << " mean " << means[x] << " seed " << seed;
    }
    EXPECT_EQ(a.next(), b.next());
  }
}

}  // namespace
}  // namespace fss
