// Tests of fss/noise.h: the random streams, the Poisson variate of Algorithm 1
// (docs/method.md §3) and PoissonSNR. Statistical checks use fixed seeds and a 5
// standard error band, so they are deterministic and fail only on a real bias.

#include "fss/model/noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fss/core/error.h"

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
  std::vector<std::uint64_t> out;
  for (int i = 0; i < count; ++i) out.push_back(stream.next());
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
    for (int sampler = 0; sampler < 2; ++sampler) {
      try {
        if (sampler == 0) {
          PoissonSNR noise(snr);
        } else {
          PoissonRowSampler row_sampler(snr);
        }
        ADD_FAILURE() << "snr " << snr << " accepted (sampler " << sampler << ")";
      } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::kUsage);
        EXPECT_NE(std::string(error.what()).find("snr"), std::string::npos) << error.what();
      }
    }
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

}  // namespace
}  // namespace fss
