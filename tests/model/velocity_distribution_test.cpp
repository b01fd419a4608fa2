// Velocity distributions (fss/model/velocity_distribution.h): the text forms and their rules, the
// file of velocities, the per-trial draws and the two quadratures.
#include "fss/model/velocity_distribution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fss/core/error.h"

namespace fss {
namespace {

VelocityDistribution parsed(const std::string& text) {
  VelocityDistribution d;
  std::string error;
  EXPECT_TRUE(parse_velocity_distribution(text, &d, &error)) << text << ": " << error;
  return d;
}

// Composite Simpson on [a, b] with n (even) intervals: the reference for the quadratures.
template <typename F>
double simpson(const F& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

TEST(VelocityDistributionText, EveryFormReadsBack) {
  for (const std::string text : {"uniform:0.5:1.5", "normal:1:0.2", "normal:1:0.2:0.5:1.2",
                                 "uniform:-2:-1", "uniform:1:1"}) {
    EXPECT_EQ(parsed(text).text(), text);
  }
  const VelocityDistribution normal = parsed("normal:1:0.25");
  EXPECT_DOUBLE_EQ(normal.low, 0.0);
  EXPECT_DOUBLE_EQ(normal.high, 2.0);
  EXPECT_NE(normal.describe().find("truncated at mean +/- 4 sd"), std::string::npos);
  EXPECT_NE(normal.describe().find("renormalised"), std::string::npos);
  EXPECT_EQ(parsed("uniform:-3:2").max_abs_velocity(), 3.0);
  EXPECT_TRUE(parsed("uniform:1:1").is_point());
  EXPECT_FALSE(parsed("uniform:1:1.5").is_point());
}

TEST(VelocityDistributionText, RefusesMalformedOrEmptyDistributions) {
  for (const std::string text :
       {"", "uniform", "uniform:1", "uniform:1:2:3", "uniform:2:1", "uniform:nan:1",
        "uniform:1:inf", "normal:1", "normal:1:0", "normal:1:-1", "normal:1:0.1:2:3e9",
        "normal:0:1e-3:50:60", "normal:1:0.2:1:1", "gauss:1:2", "uniform:1e7:1e7", "uniform::1",
        "uniform:1:2:"}) {
    VelocityDistribution d;
    std::string error;
    EXPECT_FALSE(parse_velocity_distribution(text, &d, &error)) << text;
    EXPECT_NE(error.find("velocity distribution"), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST(VelocityDistributionMoments, DensityIntegratesToOneAndMeansAgree) {
  for (const std::string text : {"uniform:0.5:1.5", "normal:1:0.2", "normal:1:0.3:0.8:2"}) {
    const VelocityDistribution d = parsed(text);
    const double mass = simpson([&](double v) { return d.density(v); }, d.low, d.high, 4000);
    EXPECT_NEAR(mass, 1.0, 1e-9) << text;
    const double mean = simpson([&](double v) { return v * d.density(v); }, d.low, d.high, 4000);
    EXPECT_NEAR(d.expected_velocity(), mean, 1e-9) << text;
    // The quantile inverts the distribution function.
    for (const double u : {0.01, 0.25, 0.5, 0.9}) {
      const double v = d.quantile(u);
      const double cdf = simpson([&](double x) { return d.density(x); }, d.low, v, 4000);
      EXPECT_NEAR(cdf, u, 1e-8) << text << " u " << u;
    }
    EXPECT_EQ(d.quantile(0.0), d.low);
    EXPECT_EQ(d.quantile(1.0), d.high);
  }
}

TEST(DiscreteVelocities, MergedSortedAndNormalised) {
  VelocityDistribution d;
  std::string error;
  ASSERT_TRUE(discrete_velocity_distribution({{1.5, 1.0}, {0.5, 1.0}, {1.0, 1.0}, {1.0, 1.0}}, "",
                                             &d, &error))
      << error;
  ASSERT_EQ(d.points.size(), 3u);
  EXPECT_EQ(d.points[0].velocity, 0.5);
  EXPECT_DOUBLE_EQ(d.points[1].weight, 0.5);
  EXPECT_EQ(d.low, 0.5);
  EXPECT_EQ(d.high, 1.5);
  EXPECT_DOUBLE_EQ(d.expected_velocity(), 1.0);
  EXPECT_EQ(d.quantile(0.2), 0.5);
  EXPECT_EQ(d.quantile(0.26), 1.0);
  EXPECT_EQ(d.quantile(0.76), 1.5);
  EXPECT_EQ(d.density(1.0), 0.0);
  EXPECT_FALSE(discrete_velocity_distribution({{1.0, 0.0}}, "", &d, &error));
  EXPECT_FALSE(discrete_velocity_distribution({{1.0, -1.0}}, "", &d, &error));
  EXPECT_FALSE(discrete_velocity_distribution({{NAN, 1.0}}, "", &d, &error));
  EXPECT_FALSE(discrete_velocity_distribution({}, "", &d, &error));
}

class VelocityFile : public ::testing::Test {
 protected:
  std::filesystem::path path_ =
      std::filesystem::temp_directory_path() /
      ("fss_velocity_file_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
       "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".txt");
  void write(const std::string& text) { std::ofstream(path_, std::ios::binary) << text; }
  void TearDown() override { std::filesystem::remove(path_); }
  // The message of the fss::Error load_velocity_distribution throws, and its kind.
  std::pair<std::string, ErrorKind> refusal(const std::string& spec) {
    try {
      load_velocity_distribution(spec, "--velocity-distribution");
    } catch (const Error& e) {
      return {e.what(), e.kind()};
    }
    ADD_FAILURE() << spec << " was accepted";
    return {"", ErrorKind::kRuntime};
  }
};

TEST_F(VelocityFile, ReadsVelocityWeightLines) {
  write("# velocity weight\n0.5 1\n\n1.0\t2   # the centre\n1.5 1\r\n");
  const VelocityDistribution d = load_velocity_distribution(path_.string(), "x");
  EXPECT_EQ(d.kind, VelocityDistributionKind::kDiscrete);
  ASSERT_EQ(d.points.size(), 3u);
  EXPECT_DOUBLE_EQ(d.points[1].weight, 0.5);
  EXPECT_EQ(d.text(), path_.string());
  EXPECT_EQ(load_velocity_distribution("uniform:1:2", "x").text(), "uniform:1:2");
}

TEST_F(VelocityFile, RefusesWhatItCannotRead) {
  write("0.5 1\n1.0 2 3\n");
  auto [message, kind] = refusal(path_.string());
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
  EXPECT_EQ(kind, ErrorKind::kRuntime);
  write("0.5 x\n");
  EXPECT_NE(refusal(path_.string()).first.find("'x' is not a finite number"), std::string::npos);
  write("0.5 0\n");
  EXPECT_NE(refusal(path_.string()).first.find("weight"), std::string::npos);
  write("# nothing\n");
  EXPECT_NE(refusal(path_.string()).first.find("holds no velocity"), std::string::npos);
  std::string many;
  for (int i = 0; i <= kMaxDiscreteVelocities; ++i) many += std::to_string(i) + " 1\n";
  write(many);
  EXPECT_NE(refusal(path_.string()).first.find("more than"), std::string::npos);
  write(std::string(kMaxVelocityFileBytes + 10, '#'));
  EXPECT_NE(refusal(path_.string()).first.find("larger than"), std::string::npos);
  const auto [missing, missing_kind] = refusal(path_.string() + ".missing");
  EXPECT_NE(missing.find("--velocity-distribution"), std::string::npos) << missing;
  EXPECT_EQ(missing_kind, ErrorKind::kUsage);
  EXPECT_EQ(refusal("uniform:2:1").second, ErrorKind::kUsage);
  EXPECT_EQ(refusal(std::filesystem::temp_directory_path().string()).second, ErrorKind::kRuntime);
}

TEST(TrialVelocity, DependsOnSeedAndTrialOnlyAndFollowsTheDistribution) {
  const VelocityDistribution d = parsed("uniform:0.5:1.5");
  EXPECT_EQ(trial_velocity(d, 7, 3), trial_velocity(d, 7, 3));
  EXPECT_NE(trial_velocity(d, 7, 3), trial_velocity(d, 7, 4));
  EXPECT_NE(trial_velocity(d, 7, 3), trial_velocity(d, 8, 3));
  // The mean of n draws against the exact mean, for several seeds: z within 4.
  const VelocityDistribution normal = parsed("normal:1:0.2:0.7:1.6");
  for (const std::uint64_t seed : {0u, 1u, 2u, 3u}) {
    for (const VelocityDistribution* dist : {&d, &normal}) {
      constexpr int kDraws = 20000;
      double sum = 0.0;
      double sum_sq = 0.0;
      for (int t = 0; t < kDraws; ++t) {
        const double v = trial_velocity(*dist, seed, static_cast<std::uint64_t>(t));
        ASSERT_GE(v, dist->low);
        ASSERT_LE(v, dist->high);
        sum += v;
        sum_sq += v * v;
      }
      const double mean = sum / kDraws;
      const double sd = std::sqrt((sum_sq - kDraws * mean * mean) / (kDraws - 1));
      EXPECT_LT(std::abs(mean - dist->expected_velocity()) / (sd / std::sqrt(kDraws)), 4.0)
          << dist->text() << " seed " << seed;
    }
  }
}

TEST(VelocityQuadrature, GaussRuleIsExactForPolynomialsOnUniform) {
  const VelocityDistribution d = parsed("uniform:0.5:1.5");
  const std::vector<VelocityNode> nodes = composite_gauss_nodes(d);
  EXPECT_EQ(nodes.size(), static_cast<std::size_t>(kDesignVelocityPanels * kDesignVelocityOrder));
  double sum = 0.0;
  for (const VelocityNode& n : nodes) sum += n.weight * std::pow(n.velocity, 7);
  // E[V^7] = (1.5^8 - 0.5^8) / 8 for V uniform on [0.5, 1.5].
  EXPECT_NEAR(sum, (std::pow(1.5, 8) - std::pow(0.5, 8)) / 8.0, 1e-13);
  const std::vector<VelocityNode> one = composite_gauss_nodes(parsed("uniform:1:1"));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].velocity, 1.0);
  EXPECT_EQ(one[0].weight, 1.0);
  EXPECT_THROW(composite_gauss_nodes(d, 0, 4), Error);
}

TEST(VelocityQuadrature, AdaptiveRuleReachesItsToleranceOnAPeakedIntegrand) {
  // A peak of width 1e-3 at 1.01, as 1 / |K|^2 near a velocity where K nearly vanishes.
  const auto peaked = [](double v) { return 1.0 / ((v - 1.01) * (v - 1.01) + 1e-6); };
  for (const std::string text : {"uniform:0.5:1.5", "normal:1:0.2"}) {
    const VelocityDistribution d = parsed(text);
    std::vector<VelocityNode> rule;
    const VelocityExpectation e = expected_over_velocity(d, peaked, 1e-4, 256, &rule);
    const double reference =
        simpson([&](double v) { return peaked(v) * d.density(v); }, d.low, d.high, 2000000);
    EXPECT_TRUE(e.converged) << text;
    EXPECT_LT(std::abs(e.value - reference), 1e-4 * reference) << text;
    EXPECT_GT(e.intervals, 1) << text;
    // The rule reproduces the value for the same function.
    double again = 0.0;
    for (const VelocityNode& n : rule) again += n.weight * peaked(n.velocity);
    EXPECT_NEAR(again, e.value, 1e-12 * e.value) << text;
    EXPECT_EQ(rule.size(), static_cast<std::size_t>(15 * e.intervals));
  }
}

TEST(VelocityQuadrature, DiscreteIsTheWeightedSumAndInfinityPropagates) {
  VelocityDistribution d;
  std::string error;
  ASSERT_TRUE(discrete_velocity_distribution({{1.0, 3.0}, {2.0, 1.0}}, "", &d, &error));
  const VelocityExpectation e = expected_over_velocity(d, [](double v) { return v * v; });
  EXPECT_EQ(e.value, 0.75 * 1.0 + 0.25 * 4.0);
  EXPECT_EQ(e.evaluations, 2);
  const VelocityExpectation inf = expected_over_velocity(parsed("uniform:0.5:1.5"), [](double v) {
    return v > 1.2 ? std::numeric_limits<double>::infinity() : 1.0;
  });
  EXPECT_TRUE(std::isinf(inf.value));
  EXPECT_FALSE(std::isnan(inf.value));
  // Budget spent: said so.
  const VelocityExpectation capped = expected_over_velocity(
      parsed("uniform:0:1"), [](double v) { return v < 0.3 ? 0.0 : 1.0; }, 1e-12, 12);
  EXPECT_FALSE(capped.converged);
  EXPECT_EQ(capped.intervals, 12);
  // One starting interval is refined too.
  const VelocityExpectation one = expected_over_velocity(
      parsed("uniform:0:1"), [](double v) { return v < 0.3 ? 0.0 : 1.0; }, 1e-6, 256, nullptr, 1);
  EXPECT_NEAR(one.value, 0.7, 1e-6);
}

}  // namespace
}  // namespace fss
