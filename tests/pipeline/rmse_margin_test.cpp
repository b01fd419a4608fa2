// --rmse-margin auto (geometry.h, rmse_margin): the paper's 3B wherever it leaves an RMSE
// window, else the largest margin leaving a window of B columns; every width with a
// contrast-invariant window can run; a wide image gives the default run bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/simulate.h"
#include "support/test_util.h"

namespace fss {
namespace {

// Every width from the smallest with any output to beyond 9B + 1, for a few blur lengths.
template <typename F>
void for_each_width(F&& f) {
  for (const int length : {1, 7, 52}) {
    for (const double velocity : {0.5, 1.0, 1.5, 2.7}) {
      const int b = std::max(length, static_cast<int>(std::ceil(velocity * length)));
      for (int width = 3 * b + 1; width <= 11 * b; ++width) {
        f(Geometry::compute(width, length, velocity, 1.0), length, velocity);
      }
    }
  }
}

TEST(RmseMarginAuto, IsThreeBWhereverThePapersMarginLeavesAWindow) {
  for_each_width([](const Geometry& g, int, double) {
    const int b = g.blur_length;
    if (g.width < 9 * b + 1) return;
    EXPECT_EQ(rmse_margin(g, kRmseMarginAuto), 3 * b) << g.width;
    const MetricWindows automatic = metric_windows(g, kRmseMarginAuto);
    const MetricWindows paper = metric_windows(g, kRmseMarginDefault);
    EXPECT_EQ(automatic.rmse_first, paper.rmse_first);
    EXPECT_EQ(automatic.rmse_end, paper.rmse_end);
  });
}

TEST(RmseMarginAuto, IsTheLargestMarginLeavingBColumnsOnNarrowerImages) {
  for_each_width([](const Geometry& g, int, double) {
    const int b = g.blur_length;
    if (g.width >= 9 * b + 1 || g.width < 5 * b + 1) return;
    const int m = rmse_margin(g, kRmseMarginAuto);
    const int window = g.output_width - 2 * m;
    EXPECT_GE(m, 0);
    EXPECT_LT(m, 3 * b);
    EXPECT_GE(window, b) << g.width;
    EXPECT_LT(g.output_width - 2 * (m + 1), b) << "a larger margin would do: " << g.width;
    const MetricWindows w = metric_windows(g, kRmseMarginAuto);
    EXPECT_EQ(w.rmse_first, m);
    EXPECT_EQ(w.rmse_end, g.output_width - m);
  });
}

TEST(RmseMarginAuto, EveryWidthWithAContrastInvariantWindowRuns) {
  for_each_width([](const Geometry& g, int length, double velocity) {
    const int b = g.blur_length;
    const std::string reason =
        too_narrow_reason(g.width, length, velocity, 1.0, kRmseMarginAuto, nullptr);
    EXPECT_EQ(reason.empty(), g.width >= 5 * b + 1) << g.width << ": " << reason;
    const std::string paper =
        too_narrow_reason(g.width, length, velocity, 1.0, kRmseMarginDefault, nullptr);
    EXPECT_EQ(paper.empty(), g.width >= 9 * b + 1) << g.width << ": " << paper;
  });
}

SimulationOptions options_with(int margin) {
  SimulationOptions o;
  o.seed = 5;
  o.trials = 2;
  o.threads = 1;
  o.rmse_margin_columns = margin;
  return o;
}

TEST(RmseMarginAuto, AWideImageGivesTheDefaultRunBitForBit) {
  const Image image = test::make_test_image(600, 6, 1);  // B = 52: 9B + 1 = 469
  const ShutterCode code = builtin_code("raskar").value();
  const SimulationReport paper = Simulate(options_with(kRmseMarginDefault), image, code);
  const SimulationReport automatic = Simulate(options_with(kRmseMarginAuto), image, code);
  EXPECT_EQ(automatic.rmse_first, 3 * 52);
  EXPECT_EQ(automatic.metrics.rmse, paper.metrics.rmse);
  EXPECT_EQ(automatic.trials.rmse_mean, paper.trials.rmse_mean);
  EXPECT_EQ(automatic.prediction.rmse, paper.prediction.rmse);
  EXPECT_EQ(automatic.warnings, paper.warnings);
  EXPECT_EQ(automatic.restored.data, paper.restored.data);
}

TEST(RmseMarginAuto, ANarrowImageRunsWithTheReducedMarginAndSaysSo) {
  const Image image = test::make_test_image(600, 6, 1);
  const ShutterCode code = builtin_code("raskar").value();
  SimulationOptions o = options_with(kRmseMarginAuto);
  o.velocity_px_per_slot = 1.5;  // B = 78: 5B + 1 = 391 <= 600 < 703 = 9B + 1
  SimulationOptions paper = o;
  paper.rmse_margin_columns = kRmseMarginDefault;
  const auto refused = test::error_of([&] { Simulate(paper, image, code); });
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->kind(), ErrorKind::kUsage);
  const SimulationReport r = Simulate(o, image, code);
  const int wo = 600 - 3 * 78;
  EXPECT_EQ(r.rmse_first, (wo - 78) / 2);
  EXPECT_EQ(r.rmse_end - r.rmse_first, 78);
  const auto said = [](const std::vector<std::string>& warnings) {
    return std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
      return w.find("RMSE margin auto: 144 columns, below the paper's 3B = 234") == 0;
    });
  };
  EXPECT_EQ(said(r.warnings), 1);
  EXPECT_TRUE(std::isfinite(r.metrics.rmse));
  // The same window given as a number is the same run, without the warning.
  SimulationOptions given = o;
  given.rmse_margin_columns = r.rmse_first;
  const SimulationReport same = Simulate(given, image, code);
  EXPECT_EQ(same.metrics.rmse, r.metrics.rmse);
  EXPECT_EQ(same.prediction.rmse, r.prediction.rmse);
  EXPECT_EQ(said(same.warnings), 0);
  EXPECT_EQ(same.warnings.size() + 1, r.warnings.size());
}

}  // namespace
}  // namespace fss
