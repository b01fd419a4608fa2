// Tests of src/pipeline/noise_weights.h (docs/method.md §6b): the noise
// weights against the restoration itself applied to unit impulses.

#include "pipeline/noise_weights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "pipeline/restore.h"
#include "support/test_util.h"

namespace fss {
namespace {

// W(j) by brute force: RowRestorer on an observation whose only nonzero
// column is observed-crop column j (observation column h + j), the squares
// of the restored window summed.
std::vector<double> weights_by_impulses(const Geometry& g, const std::vector<double>& gains,
                                        double velocity, double dt, int first, int end) {
  const RowRestorer restorer(g, gains, velocity, dt);
  RowRestorer::Scratch scratch(restorer);
  std::vector<double> observation(static_cast<std::size_t>(g.width));
  std::vector<double> restored(static_cast<std::size_t>(g.output_width));
  std::vector<double> weights;
  for (int j = 0; j < g.observed_width; ++j) {
    std::fill(observation.begin(), observation.end(), 0.0);
    observation[static_cast<std::size_t>(g.half_blur) + static_cast<std::size_t>(j)] = 1.0;
    restorer.restore(observation.data(), scratch, restored.data());
    double sum = 0.0;
    for (int x = first; x < end; ++x) sum += restored[x] * restored[x];
    weights.push_back(sum);
  }
  return weights;
}

std::vector<double> random_code(int length, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> gain(0.0, 1.0);
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (double& a : gains) a = gain(rng);
  return gains;
}

struct Case {
  std::string name;
  int width;
  std::vector<double> gains;
  double velocity;
  double dt;
  int margin;  // window [margin, Wo - margin)
  int expected_zero_bins;
};

class NoiseEnergyWeights : public ::testing::TestWithParam<Case> {};

TEST_P(NoiseEnergyWeights, AreTheRestorationsEnergyOfEachUnitImpulse) {
  const Case& c = GetParam();
  const auto length = static_cast<int>(c.gains.size());
  const Geometry g = Geometry::compute(c.width, length, c.velocity, c.dt);
  const int first = c.margin;
  const int end = g.output_width - c.margin;
  ASSERT_LT(first, end);
  int zero_bins = 0;
  for (const Complex& k : transfer_function_bins(c.gains, c.velocity, c.dt, g.mirror_width)) {
    zero_bins += k == Complex(0.0) ? 1 : 0;
  }
  EXPECT_EQ(zero_bins, c.expected_zero_bins);
  const std::vector<double> w = noise_energy_weights(g, c.gains, c.velocity, c.dt, first, end);
  const std::vector<double> expected =
      weights_by_impulses(g, c.gains, c.velocity, c.dt, first, end);
  ASSERT_EQ(w.size(), static_cast<std::size_t>(g.observed_width));
  double largest = 0.0;
  for (std::size_t j = 0; j < w.size(); ++j) {
    EXPECT_NEAR(w[j], expected[j], 1e-12 * expected[j]) << c.name << " column " << j;
    largest = std::max(largest, w[j]);
  }
  EXPECT_GT(largest, 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Geometries, NoiseEnergyWeights,
    ::testing::Values(Case{"raskar_v1", 300, test::paper_gains("raskar"), 1.0, 1.0, 52, 0},
                      Case{"odd_width_slow", 201, random_code(8, 1), 0.5, 1.0, 3, 0},
                      Case{"odd_width_fast", 163, random_code(8, 2), 1.7, 1.0, 0, 0},
                      // |v| dt = 2 exactly puts a zero of sinc_h on the Nyquist bin, rounded
                      // to about 1e-16: 1 / K ~ 1e16 leaves no digit to compare. Just below:
                      Case{"negative_velocity_near_two", 171, random_code(7, 3), -1.95, 1.0, 5, 0},
                      Case{"half_dt", 157, random_code(9, 4), 1.0, 0.5, 1, 0},
                      Case{"velocity_dt_one", 155, random_code(6, 5), -0.5, 2.0, 0, 0},
                      // Gains summing to 0: K(0) = 0 exactly, a bin left at 0.
                      Case{"zero_bin", 140, {1.0, 2.0, -3.0, 0.5, -0.5}, 1.0, 1.0, 2, 1}),
    [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

// The window is the sum's range: W over [a, c) is W over [a, b) plus W over [b, c).
TEST(NoiseEnergyWeightsWindow, AddsOverSplitWindows) {
  const std::vector<double> gains = random_code(10, 6);
  const Geometry g = Geometry::compute(250, 10, 0.8, 1.0);
  const auto whole = noise_energy_weights(g, gains, 0.8, 1.0, 4, 200);
  const auto left = noise_energy_weights(g, gains, 0.8, 1.0, 4, 77);
  const auto right = noise_energy_weights(g, gains, 0.8, 1.0, 77, 200);
  for (std::size_t j = 0; j < whole.size(); ++j) {
    EXPECT_NEAR(whole[j], left[j] + right[j], 1e-12 * whole[j]) << j;
  }
}

// Snapshot at v = 0: K = dt everywhere, the restoration copies the crop
// (over dt): output column x is observed-crop column x + h, w_x(j) = [j = x + h] / dt.
TEST(NoiseEnergyWeightsWindow, SnapshotAtRestIsTheCropOverDt) {
  const std::vector<double> gains = {1.0};
  const Geometry g = Geometry::compute(40, 1, 0.0, 0.5);
  const auto w = noise_energy_weights(g, gains, 0.0, 0.5, 3, 30);
  for (int j = 0; j < g.observed_width; ++j) {
    const int x = j - g.half_blur;
    EXPECT_NEAR(w[j], x >= 3 && x < 30 ? 4.0 : 0.0, 1e-13) << j;
  }
}

TEST(NoiseEnergyWeightsWindow, RefusesBadWindowsAndCodes) {
  const std::vector<double> gains = random_code(8, 7);
  const Geometry g = Geometry::compute(100, 8, 1.0, 1.0);
  for (const auto& window : {std::pair{5, 5}, {-1, 10}, {0, g.output_width + 1}, {9, 3}}) {
    const int first = window.first;
    const int end = window.second;
    EXPECT_TRUE(test::throws_error([&] { noise_energy_weights(g, gains, 1.0, 1.0, first, end); },
                                   ErrorKind::kUsage, {"window", std::to_string(first)}));
  }
  EXPECT_TRUE(test::throws_error([&] { noise_energy_weights(g, {}, 1.0, 1.0, 0, 10); },
                                 ErrorKind::kUsage, {"gain"}));
  EXPECT_TRUE(test::throws_error([&] { noise_energy_weights(Geometry(), gains, 1.0, 1.0, 0, 1); },
                                 ErrorKind::kUsage, {"Wa = 0"}));
}

}  // namespace
}  // namespace fss
