// Tests of src/model/noise.h: the random streams, the Poisson variate of
// Algorithm 1 (docs/method.md §3), PoissonSNR, its exact variance and the
// aggregated sampler (docs/method.md §6c). Statistical checks use fixed
// seeds and a 5 (4 for the per-pixel maps) standard error band, so they are
// deterministic and fail only on a real bias.

#include "model/noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "support/test_util.h"

namespace fss {
namespace {

struct Moments {
  double mean = 0.0;
  double variance = 0.0;  // unbiased sample variance
};

template <typename Draw>
Moments sample_moments(int n, Draw draw) {
  // Welford's update keeps the variance accurate for large means.
  double mean = 0.0;
  double m2 = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double x = draw();
    const double delta = x - mean;
    mean += delta / i;
    m2 += delta * (x - mean);
  }
  return {mean, m2 / (n - 1)};
}

std::vector<std::uint64_t> first_outputs(RandomStream stream, int count) {
  std::vector<std::uint64_t> out(static_cast<std::size_t>(count));
  for (auto& value : out) value = stream.next();
  return out;
}

TEST(RandomStream, SameCoordinatesSameSequence) {
  RandomStream a(42, 1, 7, 300);
  RandomStream b(42, 1, 7, 300);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next(), b.next()) << i;
  RandomStream c(42, 1, 7, 300);
  RandomStream d(42, 1, 7, 300);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(c.uniform(), d.uniform()) << i;
    ASSERT_EQ(c.standard_normal(), d.standard_normal()) << i;
  }
}

TEST(RandomStream, EachCoordinateChangesTheSequence) {
  const auto base = first_outputs(RandomStream(42, 1, 7, 300), 4);
  const std::vector<RandomStream> changed = {
      RandomStream(43, 1, 7, 300), RandomStream(42, 2, 7, 300), RandomStream(42, 1, 8, 300),
      RandomStream(42, 1, 7, 301), RandomStream(0, 1, 7, 300),  RandomStream(42, 0, 7, 300),
      RandomStream(42, 1, 0, 300), RandomStream(42, 1, 7, 0)};
  for (std::size_t i = 0; i < changed.size(); ++i) {
    const auto other = first_outputs(changed[i], 4);
    // A 64-bit collision by chance has probability 2^-64.
    EXPECT_NE(other[0], base[0]) << "variant " << i;
    EXPECT_NE(other, base) << "variant " << i;
  }
}

TEST(RandomStream, CoordinatesAreNotInterchangeable) {
  // (channel, frame, row) = (1, 0, 0), (0, 1, 0), (0, 0, 1) and the zero
  // stream must all differ: each coordinate has its own role.
  const std::vector<std::vector<std::uint64_t>> streams = {
      first_outputs(RandomStream(5, 0, 0, 0), 2), first_outputs(RandomStream(5, 1, 0, 0), 2),
      first_outputs(RandomStream(5, 0, 1, 0), 2), first_outputs(RandomStream(5, 0, 0, 1), 2),
      first_outputs(RandomStream(0, 5, 0, 0), 2), first_outputs(RandomStream(1, 0, 0, 0), 2)};
  for (std::size_t i = 0; i < streams.size(); ++i) {
    for (std::size_t j = i + 1; j < streams.size(); ++j) {
      EXPECT_NE(streams[i][0], streams[j][0]) << i << " vs " << j;
    }
  }
}

TEST(RandomStream, UniformRangeAndResolution) {
  RandomStream stream(7, 0, 0, 0);
  for (int i = 0; i < 100000; ++i) {
    const double u = stream.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    // 53 random bits: u is a multiple of 2^-53.
    const double scaled = std::ldexp(u, 53);
    ASSERT_EQ(scaled, std::floor(scaled)) << u;
  }
}

TEST(RandomStream, UniformOpenZeroRange) {
  RandomStream stream(8, 0, 0, 0);
  for (int i = 0; i < 100000; ++i) {
    const double u = stream.uniform_open_zero();
    ASSERT_GT(u, 0.0);
    ASSERT_LE(u, 1.0);
    ASSERT_TRUE(std::isfinite(std::log(u)));
  }
}

TEST(RandomStream, UniformMean) {
  const int n = 1000000;
  RandomStream stream(9, 2, 3, 4);
  const Moments m = sample_moments(n, [&] { return stream.uniform(); });
  // 5 standard errors: sd of U(0,1) is sqrt(1/12).
  EXPECT_NEAR(m.mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
  // Variance 1/12; SE of the sample variance sqrt((mu4 - sigma^4) / n), mu4 = 1/80.
  EXPECT_NEAR(m.variance, 1.0 / 12.0, 5.0 * std::sqrt((1.0 / 80.0 - 1.0 / 144.0) / n));

  RandomStream open(9, 2, 3, 5);
  const Moments mo = sample_moments(n, [&] { return open.uniform_open_zero(); });
  EXPECT_NEAR(mo.mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));  // 5 standard errors
}

TEST(RandomStream, StandardNormalMoments) {
  const int n = 1000000;
  RandomStream stream(10, 0, 1, 2);
  const Moments m = sample_moments(n, [&] { return stream.standard_normal(); });
  // 5 standard errors: SE of the mean 1/sqrt(n), of the variance sqrt(2/n).
  EXPECT_NEAR(m.mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(m.variance, 1.0, 5.0 * std::sqrt(2.0 / n));
}

TEST(RandomStream, StandardNormalSuccessiveDrawsUncorrelated) {
  // The cosine value and its sine twin are independent normals; a twin that
  // repeated or negated the first draw would show up here.
  const int n = 500000;
  RandomStream stream(11, 0, 0, 0);
  double sum_product = 0.0;
  double previous = stream.standard_normal();
  for (int i = 0; i < n; ++i) {
    const double x = stream.standard_normal();
    sum_product += previous * x;
    previous = x;
  }
  // E[X Y] = 0 with sd 1 per term: 5 standard errors of the mean.
  EXPECT_NEAR(sum_product / n, 0.0, 5.0 / std::sqrt(n));
}

// Poisson sample moments against lambda with a 5 standard error band.
void expect_poisson_moments(double lambda, std::uint64_t seed) {
  const int n = 200000;
  RandomStream stream(seed, 0, 0, 0);
  bool all_integers = true;
  const Moments m = sample_moments(n, [&] {
    const double x = poisson_variate(lambda, stream);
    if (!(x >= 0.0 && x == std::floor(x))) all_integers = false;
    return x;
  });
  EXPECT_TRUE(all_integers) << "lambda " << lambda;
  // SE of the mean sqrt(lambda / n).
  EXPECT_NEAR(m.mean, lambda, 5.0 * std::sqrt(lambda / n)) << "lambda " << lambda;
  // SE of the sample variance sqrt((mu4 - sigma^4) / n), mu4 = lambda + 3 lambda^2.
  const double mu4 = lambda + 3.0 * lambda * lambda;
  EXPECT_NEAR(m.variance, lambda, 5.0 * std::sqrt((mu4 - lambda * lambda) / n))
      << "lambda " << lambda;
}

TEST(PoissonVariate, KnuthBranchMoments) { expect_poisson_moments(5.0, 101); }

TEST(PoissonVariate, NormalBranchMoments) { expect_poisson_moments(5000.0, 102); }

TEST(PoissonVariate, JustBelowTheSwitch) { expect_poisson_moments(49.9, 103); }

TEST(PoissonVariate, JustAboveTheSwitch) { expect_poisson_moments(50.1, 104); }

TEST(PoissonVariate, SmallIntensities) {
  expect_poisson_moments(0.3, 105);
  expect_poisson_moments(1.0, 106);
}

TEST(PoissonVariate, KnuthBranchDistribution) {
  // P(X = k) = exp(-5) 5^k / k! for k = 0 .. 12, each frequency within 5
  // binomial standard errors: catches an off-by-one in the multiplication count.
  const int n = 200000;
  const double lambda = 5.0;
  std::vector<int> counts(13, 0);
  RandomStream stream(107, 0, 0, 0);
  for (int i = 0; i < n; ++i) {
    const double x = poisson_variate(lambda, stream);
    if (x < static_cast<double>(counts.size())) ++counts[static_cast<std::size_t>(x)];
  }
  double p = std::exp(-lambda);
  for (std::size_t k = 0; k < counts.size(); ++k) {
    if (k > 0) p *= lambda / static_cast<double>(k);
    const double frequency = static_cast<double>(counts[k]) / n;
    EXPECT_NEAR(frequency, p, 5.0 * std::sqrt(p * (1.0 - p) / n) + 1.0 / n) << "k " << k;
  }
}

TEST(PoissonVariate, ZeroAndNegativeIntensityGiveZero) {
  RandomStream stream(108, 0, 0, 0);
  for (const double lambda : {0.0, -0.0, -1e-300, -1.0, -60.0, -1e9}) {
    for (int i = 0; i < 100; ++i) EXPECT_EQ(poisson_variate(lambda, stream), 0.0) << lambda;
  }
}

TEST(PoissonVariate, Reproducible) {
  RandomStream a(109, 2, 3, 4);
  RandomStream b(109, 2, 3, 4);
  for (const double lambda : {0.5, 7.0, 49.99, 50.0, 123.0, 1e6}) {
    for (int i = 0; i < 200; ++i) {
      ASSERT_EQ(poisson_variate(lambda, a), poisson_variate(lambda, b)) << lambda;
    }
  }
}

TEST(PoissonSNR, Lambda2IsSnrSquaredOver100) {
  EXPECT_DOUBLE_EQ(PoissonSNR(100.0).lambda2(), 100.0);
  EXPECT_DOUBLE_EQ(PoissonSNR(10.0).lambda2(), 1.0);
  EXPECT_DOUBLE_EQ(PoissonSNR(3.0).lambda2(), 0.09);
  EXPECT_DOUBLE_EQ(PoissonSNR(1e6).lambda2(), 1e10);
}

// Mean e and variance e * 100 / snr^2 of PoissonSNR(e), 5 standard errors.
void expect_poisson_snr_moments(double e, double snr, std::uint64_t seed) {
  const int n = 200000;
  const PoissonSNR noise(snr);
  const double lambda2 = snr * snr / 100.0;
  const double lambda = e * lambda2;
  RandomStream stream(seed, 0, 0, 0);
  bool on_grid = true;
  const Moments m = sample_moments(n, [&] {
    const double o = noise(e, stream);
    // o = P / lambda2 with P a non-negative integer.
    const double count = o * lambda2;
    if (!(count >= 0.0 && std::abs(count - std::round(count)) < 1e-9 * (1.0 + count))) {
      on_grid = false;
    }
    return o;
  });
  EXPECT_TRUE(on_grid) << "e " << e << " snr " << snr;
  const double variance = e * 100.0 / (snr * snr);
  // SE of the mean sqrt(variance / n).
  EXPECT_NEAR(m.mean, e, 5.0 * std::sqrt(variance / n)) << "e " << e << " snr " << snr;
  // Poisson(lambda) scaled by 1/lambda2: SE of the sample variance
  // sqrt((mu4 - sigma^4) / n) / lambda2^2 with mu4 = lambda + 3 lambda^2.
  const double spread = std::sqrt((lambda + 2.0 * lambda * lambda) / n) / (lambda2 * lambda2);
  EXPECT_NEAR(m.variance, variance, 5.0 * spread) << "e " << e << " snr " << snr;
}

TEST(PoissonSNR, Level100AtSnr100) {
  // Variance e 100 / snr^2 = 1: the level-100 landscape has SNR 100.
  expect_poisson_snr_moments(100.0, 100.0, 201);
}

TEST(PoissonSNR, KnuthBranch) {
  expect_poisson_snr_moments(20.0, 10.0, 202);  // lambda = 20
  expect_poisson_snr_moments(3.0, 30.0, 203);   // lambda = 27, lambda2 = 9
}

TEST(PoissonSNR, NegativeOrZeroSignalGivesZero) {
  const PoissonSNR noise(100.0);
  RandomStream stream(204, 0, 0, 0);
  for (const double e : {0.0, -1e-12, -0.5, -100.0}) {
    for (int i = 0; i < 100; ++i) EXPECT_EQ(noise(e, stream), 0.0) << e;
  }
}

// snr^2 / 100 must be a finite normal double: 0 (snr 1e-300) makes every
// observation 0 / 0, infinity (snr 1e300) inf * 0; both are NaN.
TEST(PoissonSNR, SnrWhoseLambda2LeavesTheDoublesIsAUsageError) {
  for (const double snr : {1e300, 1e-300, 1e160, 1e-160, 0.0, -0.0}) {
    EXPECT_TRUE(test::throws_error([&] { PoissonSNR noise(snr); }, ErrorKind::kUsage, {"snr"}))
        << snr;
    EXPECT_TRUE(
        test::throws_error([&] { PoissonRowSampler sampler(snr); }, ErrorKind::kUsage, {"snr"}))
        << snr;
    EXPECT_TRUE(
        test::throws_error([&] { AggregatedRowSampler sampler(snr); }, ErrorKind::kUsage, {"snr"}))
        << snr;
  }
  // The extremes of the accepted range give finite samples.
  for (const double snr : {1e-150, 1e150}) {
    PoissonRowSampler sampler(snr);
    const std::vector<double> e = {0.0, 1.0, 100.0, 255.0};
    std::vector<double> out(e.size(), 0.0);
    sampler.accumulate(e, {1, 0, 0, 0}, 1.0, out);
    for (const double value : out) EXPECT_TRUE(std::isfinite(value)) << "snr " << snr;
  }
}

TEST(PoissonSnrVariance, ExactOnBothBranches) {
  // lambda2 = 1 (snr 10): lambda = e.
  EXPECT_EQ(poisson_snr_variance(20.0, 1.0), 20.0);
  EXPECT_EQ(poisson_snr_variance(49.5, 1.0), 49.5);
  EXPECT_EQ(poisson_snr_variance(50.0, 1.0), 50.0 + 1.0 / 12.0);
  EXPECT_EQ(poisson_snr_variance(0.0, 1.0), 0.0);
  EXPECT_EQ(poisson_snr_variance(-7.0, 1.0), 0.0);
  // lambda2 = 100 (snr 100): e = 100 is lambda = 1e4, Var = 1 + 1 / (12 1e4).
  EXPECT_DOUBLE_EQ(poisson_snr_variance(100.0, 100.0), 1.0 + 1.0 / 120000.0);
  // lambda2 = 0.25 (snr 5): e = 199.6 is lambda = 49.9, Knuth's branch.
  EXPECT_DOUBLE_EQ(poisson_snr_variance(199.6, 0.25), 199.6 / 0.25);
  EXPECT_DOUBLE_EQ(poisson_snr_variance(200.0, 0.25), 800.0 + 1.0 / (12.0 * 0.0625));
}

// Intensities in photons (lambda = max(e, 0) lambda2) on both sides of the
// switch at 50; -3 stands for a negative e.
constexpr double kMixedLambdas[] = {0.0,  -3.0, 0.4,  5.0,   31.0,  49.9,
                                    50.0, 50.7, 87.0, 400.0, 6000.0};
constexpr double kKnuthLambdas[] = {0.0, -3.0, 0.4, 5.0, 31.0, 49.9};

// One row of L = 6 frames with gains of both signs; pixel x's frame k has
// intensity table[(x + 4k) mod size], so every pixel sees 6 different
// intensities and, for the mixed table, both branches.
struct SyntheticRow {
  double lambda2 = 1.0;
  std::vector<double> gains = {1.0, -0.6, 2.5, 0.35, -1.8, 1.0};
  std::vector<std::vector<double>> e;  // e[k][x]
  std::size_t width() const { return e.front().size(); }
};

SyntheticRow synthetic_row(double snr, std::span<const double> table) {
  SyntheticRow row;
  row.lambda2 = snr * snr / 100.0;
  const std::size_t size = table.size();
  for (std::size_t k = 0; k < row.gains.size(); ++k) {
    std::vector<double> e(size);
    for (std::size_t x = 0; x < size; ++x) e[x] = table[(x + 4 * k) % size] / row.lambda2;
    row.e.push_back(e);
  }
  return row;
}

// Exact mean, variance and fourth cumulant of o[x] = sum_k alpha_k
// PoissonSNR(e_k[x]): frames are independent, so cumulants add. The fourth
// cumulant is lambda / lambda2^4 for a Poisson variate, 0 for the aggregated
// normal (and -1/120 / lambda2^4 for a rounded one: negligible here).
struct PixelLaw {
  double mean = 0.0;
  double variance = 0.0;
  double cumulant4 = 0.0;
};

PixelLaw exact_law(const SyntheticRow& row, std::size_t x) {
  PixelLaw law;
  for (std::size_t k = 0; k < row.gains.size(); ++k) {
    const double alpha = row.gains[k];
    const double e = std::max(row.e[k][x], 0.0);
    law.mean += alpha * e;
    law.variance += alpha * alpha * poisson_snr_variance(e, row.lambda2);
    const double lambda = e * row.lambda2;
    if (lambda < kKnuthLimit) law.cumulant4 += std::pow(alpha / row.lambda2, 4) * lambda;
  }
  return law;
}

enum class Sampler { kPerFrame, kAggregated };

// One draw of the row's observation, trial t as row t.
void observe_row(const SyntheticRow& row, Sampler which, std::uint64_t seed, std::uint64_t t,
                 PoissonRowSampler& per_frame, AggregatedRowSampler& aggregated,
                 std::vector<double>& out) {
  std::fill(out.begin(), out.end(), 0.0);
  for (std::size_t k = 0; k < row.gains.size(); ++k) {
    const RowNoiseId id{seed, 0, k, t};
    if (which == Sampler::kPerFrame) {
      per_frame.accumulate(row.e[k], id, row.gains[k], out);
    } else {
      aggregated.add_frame(row.e[k], id, row.gains[k], out);
    }
  }
  if (which == Sampler::kAggregated) aggregated.finish({seed, 0, 0, t}, out);
}

// Per-pixel sample mean and variance over `trials` draws against the exact
// law: z = (estimate - exact) / standard error must stay under 4 at every
// pixel. SE of the mean sqrt(var / n); of the sample variance
// sqrt(kappa4 / n + 2 var^2 / (n - 1)). Prints the largest |z|.
void expect_pixel_moments(double snr, std::span<const double> table, Sampler which,
                          std::uint64_t seed) {
  const SyntheticRow row = synthetic_row(snr, table);
  const int trials = 40000;
  const std::size_t width = row.width();
  PoissonRowSampler per_frame(snr);
  AggregatedRowSampler aggregated(snr);
  std::vector<double> out(width), mean(width, 0.0), m2(width, 0.0);
  for (int t = 1; t <= trials; ++t) {
    observe_row(row, which, seed, static_cast<std::uint64_t>(t), per_frame, aggregated, out);
    for (std::size_t x = 0; x < width; ++x) {  // Welford
      const double delta = out[x] - mean[x];
      mean[x] += delta / t;
      m2[x] += delta * (out[x] - mean[x]);
    }
  }
  const char* name = which == Sampler::kPerFrame ? "per-frame" : "aggregated";
  double worst_mean = 0.0;
  double worst_variance = 0.0;
  for (std::size_t x = 0; x < width; ++x) {
    const PixelLaw law = exact_law(row, x);
    ASSERT_GT(law.variance, 0.0) << x;
    const double variance = m2[x] / (trials - 1);
    const double z_mean = (mean[x] - law.mean) / std::sqrt(law.variance / trials);
    const double se_variance =
        std::sqrt(law.cumulant4 / trials + 2.0 * law.variance * law.variance / (trials - 1));
    const double z_variance = (variance - law.variance) / se_variance;
    EXPECT_LT(std::abs(z_mean), 4.0) << name << " snr " << snr << " pixel " << x;
    EXPECT_LT(std::abs(z_variance), 4.0) << name << " snr " << snr << " pixel " << x;
    worst_mean = std::max(worst_mean, std::abs(z_mean));
    worst_variance = std::max(worst_variance, std::abs(z_variance));
  }
  std::printf("  %s, snr %g, %zu pixels x %d draws: max |z| mean %.2f, variance %.2f\n", name, snr,
              width, trials, worst_mean, worst_variance);
}

TEST(AggregatedRowSampler, MixedBranchesMatchTheExactLawAtSnr5) {
  expect_pixel_moments(5.0, kMixedLambdas, Sampler::kAggregated, 301);
  // The per-frame sampler obeys the same law: the reference the aggregated
  // sampler must match, checked on the same rows.
  expect_pixel_moments(5.0, kMixedLambdas, Sampler::kPerFrame, 302);
}

TEST(AggregatedRowSampler, MixedBranchesMatchTheExactLawAtSnr100) {
  expect_pixel_moments(100.0, kMixedLambdas, Sampler::kAggregated, 303);
  expect_pixel_moments(100.0, kMixedLambdas, Sampler::kPerFrame, 304);
}

TEST(AggregatedRowSampler, KnuthOnlyRowsMatchThePerFrameLaw) {
  expect_pixel_moments(5.0, kKnuthLambdas, Sampler::kAggregated, 305);
  expect_pixel_moments(100.0, kKnuthLambdas, Sampler::kAggregated, 306);
}

TEST(AggregatedRowSampler, KnuthOnlyRowIsKnuthsDrawFromItsLane) {
  // With every frame below 50, the row is exactly sum_k alpha_k P_k /
  // lambda2, P_k drawn by poisson_variate from frame k's kAggregateKnuth
  // lane in pixel order, and finish() adds nothing.
  for (const double snr : {5.0, 100.0}) {
    const SyntheticRow row = synthetic_row(snr, kKnuthLambdas);
    const std::size_t width = row.width();
    AggregatedRowSampler sampler(snr);
    std::vector<double> out(width, 0.0), expected(width, 0.0);
    for (std::size_t k = 0; k < row.gains.size(); ++k) {
      sampler.add_frame(row.e[k], {7, 2, k, 9}, row.gains[k], out);
      RandomStream stream(7, 2, k, 9, static_cast<std::uint64_t>(NoiseLane::kAggregateKnuth));
      for (std::size_t x = 0; x < width; ++x) {
        const double lambda = std::max(row.e[k][x], 0.0) * sampler.lambda2();
        expected[x] += row.gains[k] / sampler.lambda2() * poisson_variate(lambda, stream);
      }
    }
    sampler.finish({7, 2, 0, 9}, out);
    EXPECT_EQ(std::memcmp(out.data(), expected.data(), width * sizeof(double)), 0) << snr;
  }
}

std::vector<double> aggregated_row(AggregatedRowSampler& sampler, const SyntheticRow& row,
                                   std::uint64_t seed, std::uint64_t channel, std::uint64_t y) {
  std::vector<double> out(row.width(), 0.0);
  for (std::size_t k = 0; k < row.gains.size(); ++k) {
    sampler.add_frame(row.e[k], {seed, channel, k, y}, row.gains[k], out);
  }
  sampler.finish({seed, channel, 0, y}, out);
  return out;
}

bool same_bytes(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(AggregatedRowSampler, SameCoordinatesSameBytes) {
  const SyntheticRow row = synthetic_row(100.0, kMixedLambdas);
  AggregatedRowSampler a(100.0);
  AggregatedRowSampler b(100.0);
  EXPECT_TRUE(same_bytes(aggregated_row(a, row, 11, 1, 5), aggregated_row(b, row, 11, 1, 5)));
}

TEST(AggregatedRowSampler, ReusedSamplerStartsEachRowAfresh) {
  // A sampler reused across rows (one per thread) gives what a fresh one
  // gives, even after a row of another width.
  const SyntheticRow row = synthetic_row(5.0, kMixedLambdas);
  const SyntheticRow narrow = synthetic_row(5.0, kKnuthLambdas);
  AggregatedRowSampler reused(5.0);
  aggregated_row(reused, row, 12, 0, 1);
  aggregated_row(reused, narrow, 12, 0, 2);
  const std::vector<double> again = aggregated_row(reused, row, 12, 0, 3);
  AggregatedRowSampler fresh(5.0);
  EXPECT_TRUE(same_bytes(again, aggregated_row(fresh, row, 12, 0, 3)));
}

TEST(AggregatedRowSampler, RowsChannelsAndSeedsDiffer) {
  // Every pixel of the mixed row has a normal-branch frame, so its value is
  // continuous: a repeat would need a 2^-53 coincidence.
  const SyntheticRow row = synthetic_row(100.0, kMixedLambdas);
  AggregatedRowSampler sampler(100.0);
  const std::vector<double> base = aggregated_row(sampler, row, 13, 0, 4);
  const std::vector<std::vector<double>> others = {aggregated_row(sampler, row, 13, 0, 5),
                                                   aggregated_row(sampler, row, 13, 1, 4),
                                                   aggregated_row(sampler, row, 14, 0, 4)};
  for (std::size_t i = 0; i < others.size(); ++i) {
    for (std::size_t x = 0; x < base.size(); ++x) {
      EXPECT_NE(others[i][x], base[x]) << "variant " << i << " pixel " << x;
    }
  }
}

TEST(AggregatedRowSampler, LanesAreDistinctStreams) {
  std::vector<std::uint64_t> firsts;
  for (const NoiseLane lane : {NoiseLane::kFrameNormal, NoiseLane::kFrameKnuth,
                               NoiseLane::kAggregateNormal, NoiseLane::kAggregateKnuth}) {
    firsts.push_back(RandomStream(1, 2, 0, 4, static_cast<std::uint64_t>(lane)).next());
  }
  std::sort(firsts.begin(), firsts.end());
  EXPECT_EQ(std::adjacent_find(firsts.begin(), firsts.end()), firsts.end());
}

TEST(AggregatedRowSampler, FinishWithoutFramesAddsNothing) {
  AggregatedRowSampler sampler(100.0);
  std::vector<double> out = {1.5, -2.0, 0.0};
  const std::vector<double> before = out;
  sampler.finish({1, 0, 0, 0}, out);
  EXPECT_TRUE(same_bytes(out, before));
  // After a row, finish() has reset the accumulators: a second one adds nothing.
  const SyntheticRow row = synthetic_row(100.0, kMixedLambdas);
  std::vector<double> drawn = aggregated_row(sampler, row, 1, 0, 0);
  const std::vector<double> once = drawn;
  sampler.finish({1, 0, 0, 0}, drawn);
  EXPECT_TRUE(same_bytes(drawn, once));
}

// A row whose frames are windows of one exposure's intensities (observe's
// circular shifts) is drawn from them as from each frame's exposure one at a
// time: the grouped frames' Lambda_g, summed when the row is drawn, in
// chunks and four frames at a time, has the bits of the frame-by-frame sum.
TEST(AggregatedRowSampler, WindowedFramesGiveTheBitsOfFramesOneAtATime) {
  // Group 1.0 of 7 frames, group 0.5 of 2, two single frames; a width that is
  // no multiple of the chunk; intensities from 0 to about 4e4 photons.
  const std::vector<double> gains = {1.0, 0.5, 1.0, 2.0, 1.0, 1.0, -0.3, 0.5, 1.0, 1.0, 1.0};
  const std::size_t w = 1300;
  const double snr = 100.0;
  AggregatedRowSampler by_frame(snr, gains);
  AggregatedRowSampler by_window(snr, gains);
  std::vector<double> e0(w);
  for (std::size_t x = 0; x < w; ++x) {  // sums that round: their order shows in the bits
    e0[x] = std::exp(7.0 * std::sin(0.37 * static_cast<double>(x))) / 3.0 - 0.5;
  }
  AggregatedRowSampler::IntensityRows rows;
  const std::size_t normal_pixels = by_window.intensities_of(e0, 0.0, rows);
  for (auto* v : {&rows.lambda, &rows.mean_part, &rows.variance_part}) {
    v->insert(v->end(), v->begin(), v->end());  // v v: each shift is a window
  }
  std::vector<double> out_frame(w, 0.0), out_window(w, 0.0);
  for (std::size_t k = 0; k < gains.size(); ++k) {
    const std::size_t offset = (37 * k) % w;  // e_k(x) = e_0((x - offset) mod w)
    std::vector<double> e(w);
    for (std::size_t x = 0; x < w; ++x) e[x] = e0[(x + w - offset) % w];
    const RowNoiseId id{5, 1, k, 3};
    by_frame.add_frame(e, id, gains[k], out_frame);
    const auto window = [&](const std::vector<double>& v) {
      return std::span<const double>(v).subspan(w - offset, w);
    };
    by_window.add_frame(
        AggregatedRowSampler::FrameIntensities{window(rows.lambda), window(rows.mean_part),
                                               window(rows.variance_part), normal_pixels},
        id, gains[k], out_window);
  }
  // Scale 1: the variances are the Lambda_g, to the last bit.
  std::vector<double> variance_frame(w, 0.0), variance_window(w, 0.0);
  by_frame.add_group_variances(variance_frame, 1.0);
  by_window.add_group_variances(variance_window, 1.0);
  EXPECT_TRUE(same_bytes(variance_frame, variance_window));
  by_frame.finish({5, 1, 0, 3}, out_frame);
  by_window.finish({5, 1, 0, 3}, out_window);
  EXPECT_TRUE(same_bytes(out_frame, out_window));
}

// Pixel x's normal as the header documents it: output x of Box-Muller pairs
// (U1, U2) taken in order from the lane's stream, here by the scalar libm
// (the samplers use the vector library or box_muller_portable, equal to a
// few ulp).
std::vector<double> documented_normals(RandomStream stream, std::size_t n) {
  std::vector<double> normals;
  while (normals.size() < n) {
    const double radius = std::sqrt(-2.0 * std::log(stream.uniform_open_zero()));
    const double angle = 2.0 * M_PI * stream.uniform();
    normals.push_back(radius * std::cos(angle));
    normals.push_back(radius * std::sin(angle));
  }
  return normals;
}

TEST(PoissonRowSampler, FollowsTheDocumentedStreamLayout) {
  // snr 10 (lambda2 = 1) and gain 1: out[x] is the photon count itself.
  // Counts on the normal branch are round(lambda + sqrt(lambda) N) with N
  // from the kFrameNormal lane; a few ulp in N change a count only within
  // about 1e-12 of a half-integer, never here. Counts on Knuth's branch are
  // poisson_variate on the kFrameKnuth lane, in pixel order.
  const std::size_t n = 1001;  // odd: the last pair's sine is unused
  std::vector<double> e(n);
  for (std::size_t x = 0; x < n; ++x) e[x] = static_cast<double>((x * 7919) % 600) - 20.0;
  PoissonRowSampler sampler(10.0);
  std::vector<double> out(n, 0.0);
  const RowNoiseId id{21, 1, 4, 33};
  sampler.accumulate(e, id, 1.0, out);
  const std::vector<double> normals = documented_normals(
      RandomStream(21, 1, 4, 33, static_cast<std::uint64_t>(NoiseLane::kFrameNormal)), n);
  RandomStream knuth(21, 1, 4, 33, static_cast<std::uint64_t>(NoiseLane::kFrameKnuth));
  for (std::size_t x = 0; x < n; ++x) {
    const double lambda = std::max(e[x], 0.0);
    const double expected = lambda < kKnuthLimit
                                ? poisson_variate(lambda, knuth)
                                : std::round(lambda + std::sqrt(lambda) * normals[x]);
    ASSERT_EQ(out[x], expected) << "pixel " << x << " lambda " << lambda;
  }
}

TEST(AggregatedRowSampler, FollowsTheDocumentedStreamLayout) {
  // out[x] = Knuth counts (kAggregateKnuth lane of each frame) +
  // (M + sqrt(V) N) / lambda2 with N from the row's kAggregateNormal lane.
  const SyntheticRow row = synthetic_row(100.0, kMixedLambdas);
  const std::size_t n = row.width();
  AggregatedRowSampler sampler(100.0);
  const std::vector<double> out = aggregated_row(sampler, row, 22, 2, 8);
  const std::vector<double> normals = documented_normals(
      RandomStream(22, 2, 0, 8, static_cast<std::uint64_t>(NoiseLane::kAggregateNormal)), n);
  std::vector<double> expected(n, 0.0), mean(n, 0.0), variance(n, 0.0);
  for (std::size_t k = 0; k < row.gains.size(); ++k) {
    const double alpha = row.gains[k];
    RandomStream knuth(22, 2, k, 8, static_cast<std::uint64_t>(NoiseLane::kAggregateKnuth));
    for (std::size_t x = 0; x < n; ++x) {
      const double lambda = std::max(row.e[k][x], 0.0) * row.lambda2;
      if (lambda < kKnuthLimit) {
        expected[x] += alpha / row.lambda2 * poisson_variate(lambda, knuth);
      } else {
        mean[x] += alpha * lambda;
        variance[x] += alpha * alpha * (lambda + 1.0 / 12.0);
      }
    }
  }
  for (std::size_t x = 0; x < n; ++x) {
    expected[x] += (mean[x] + std::sqrt(variance[x]) * normals[x]) / row.lambda2;
    EXPECT_NEAR(out[x], expected[x], 1e-12 * (std::abs(mean[x]) + std::sqrt(variance[x])))
        << "pixel " << x;
  }
}

// box_muller_portable: accurate to a few ulp of the radius (against long
// double libm), and fixed bits whatever the processor or the batch length.
TEST(BoxMullerPortable, WithinAFewUlpOfTheExactPair) {
  RandomStream stream(31, 0, 0, 0);
  const std::size_t pairs = 200000;
  std::vector<double> u1(pairs), u2(pairs), z(2 * pairs);
  for (std::size_t j = 0; j < pairs; ++j) {
    u1[j] = stream.uniform_open_zero();
    u2[j] = stream.uniform();
  }
  // The ends of both ranges and the quadrant boundaries of the angle.
  const double edges[][2] = {{0x1p-53, 0.0}, {1.0, 0.125},  {0.5, 0.25},
                             {0.25, 0.5},    {0.75, 0.75},  {0x1p-52, 1.0 - 0x1p-53},
                             {1e-9, 0.375},  {0.999, 0.625}};
  for (std::size_t i = 0; i < std::size(edges); ++i) {
    u1[i] = edges[i][0];
    u2[i] = edges[i][1];
  }
  box_muller_portable(u1.data(), u2.data(), z.data(), pairs);
  for (std::size_t j = 0; j < pairs; ++j) {
    const long double radius = std::sqrt(-2.0L * std::log(static_cast<long double>(u1[j])));
    const long double angle = 2.0L * 3.14159265358979323846264338327950288L * u2[j];
    const double tolerance = 2e-15 * static_cast<double>(radius) + 1e-300;
    ASSERT_NEAR(z[2 * j], static_cast<double>(radius * std::cos(angle)), tolerance) << "pair " << j;
    ASSERT_NEAR(z[2 * j + 1], static_cast<double>(radius * std::sin(angle)), tolerance)
        << "pair " << j;
  }
}

TEST(BoxMullerPortable, BatchEqualsPairByPair) {
  // The vectorized body and the scalar remainder of the loop give the same bits.
  RandomStream stream(32, 0, 0, 0);
  const std::size_t pairs = 1003;
  std::vector<double> u1(pairs), u2(pairs), z(2 * pairs);
  for (std::size_t j = 0; j < pairs; ++j) {
    u1[j] = stream.uniform_open_zero();
    u2[j] = stream.uniform();
  }
  box_muller_portable(u1.data(), u2.data(), z.data(), pairs);
  for (std::size_t j = 0; j < pairs; ++j) {
    double one[2];
    box_muller_portable(&u1[j], &u2[j], one, 1);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(one[0]), std::bit_cast<std::uint64_t>(z[2 * j]))
        << "pair " << j;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(one[1]), std::bit_cast<std::uint64_t>(z[2 * j + 1]))
        << "pair " << j;
  }
}

TEST(BoxMullerPortable, SameBitsOnEveryProcessor) {
  // Recorded on an AMD EPYC (AVX2); any processor, with or without AVX2 or
  // FMA, must give these bits: only correctly rounded operations are used.
  const double u1[] = {0x1p-53, 0x1.93cd7bebaf281p-1, 0x1.1bd30a60484fp-3, 0x1.ce878ee3d631p-3,
                       0x1.485066e1dd47cp-1};
  const double u2[] = {0.0, 0.25, 0.5, 0x1.fffffffffffffp-1, 0.375};
  const double expected[] = {0x1.124b2800eda48p+3,
                             0.0,
                             -0.0,
                             0x1.60cbcc86a8fefp-1,
                             -0x1.fcf3e00c535dp+0,
                             -0.0,
                             0x1.b99d4033887b2p+0,
                             -0x1.5ad7d0c6d0fe2p-50,
                             -0x1.554c6fb7b90a9p-1,
                             0x1.554c6fb7b90a8p-1};
  double z[10];
  box_muller_portable(u1, u2, z, 5);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(z[i]), std::bit_cast<std::uint64_t>(expected[i]))
        << "output " << i << ": " << z[i] << " instead of " << expected[i];
  }
}

}  // namespace
}  // namespace fss
