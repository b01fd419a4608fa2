// Simulations under a velocity distribution (docs/method.md §13), on a 480 x 16 strip of
// camera.png: the trials' mean MSE against prediction.mse (Monte Carlo under a family-wise rule,
// with its power), the trials' velocities and the thread count, a point distribution against the
// single-velocity run, the quadrature's accuracy by refinement, the infinite expectation of a
// support that reaches a velocity where the code is not invertible, and the options' rules.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/simulate.h"
#include "io/report_json_value.h"
#include "pipeline/plan_core.h"
#include "pipeline/velocity_prediction.h"
#include "support/test_util.h"

namespace fss {
namespace {

// Rows 240 .. 255 and columns 16 .. 495 of camera.png (the tripod, the coat and the grass).
const Image& camera_strip() {
  static const Image image = [] {
    const Image full = read_png(test::source_path("data/camera.png"));
    Image strip(480, 16, 1);
    for (int y = 0; y < strip.height; ++y) {
      for (int x = 0; x < strip.width; ++x) strip.at(0, y, x) = full.at(0, 240 + y, 16 + x);
    }
    return strip;
  }();
  return image;
}

// Its first 4 rows, for the tests that need no statistics (each velocity of a prediction is a
// pass over the image).
const Image& small_strip() {
  static const Image image = [] {
    Image strip(480, 4, 1);
    for (int y = 0; y < strip.height; ++y) {
      for (int x = 0; x < strip.width; ++x) strip.at(0, y, x) = camera_strip().at(0, y, x);
    }
    return strip;
  }();
  return image;
}

VelocityDistribution parsed(const std::string& spec) {
  VelocityDistribution d;
  std::string error;
  EXPECT_TRUE(parse_velocity_distribution(spec, &d, &error)) << error;
  return d;
}

VelocityDistribution three_velocities() {
  VelocityDistribution d;
  std::string error;
  EXPECT_TRUE(discrete_velocity_distribution({{0.7, 0.3}, {1.0, 0.5}, {1.3, 0.2}}, "", &d, &error))
      << error;
  return d;
}

// A run of `trials` trials under `distribution`; the RMSE margin of 40 columns fits the strip's
// width for |v| <= 1.5 (B <= 78).
SimulationOptions options_under(const VelocityDistribution& distribution, ShutterMode mode,
                                std::uint64_t seed, int trials) {
  SimulationOptions o;
  o.mode = mode;
  o.velocity_distribution = distribution;
  o.rmse_margin_columns = 40;
  o.seed = seed;
  o.trials = trials;
  o.threads = 2;
  return o;
}

ShutterCode raskar() { return *builtin_code("raskar"); }

// The standard normal's upper quantile Phi^-1(1 - p), p in (0, 0.5), by bisection.
double normal_upper_quantile(double p) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(VelocityDistributionSimulation, NormalQuantileMatchesTheTables) {
  EXPECT_NEAR(normal_upper_quantile(0.025), 1.959964, 1e-6);
  EXPECT_NEAR(normal_upper_quantile(0.0005), 3.290527, 1e-6);
}

// --- Monte Carlo -------------------------------------------------------------------------------

struct Case {
  std::string name;
  double predicted_mse = 0.0;
  double mean_mse = 0.0;
  double standard_error = 0.0;
  double z(double scale = 1.0) const { return (scale * predicted_mse - mean_mse) / standard_error; }
};

// The family-wise rule at level 2 x 0.001 over k cases: every |z| below the Bonferroni bound
// Phi^-1(1 - 0.001 / (2k)), and the mean z, times sqrt(k), within +/- Phi^-1(1 - 0.0005) (a
// shared bias of the prediction).
bool rule_passes(const std::vector<Case>& cases, double scale, bool print) {
  const double k = static_cast<double>(cases.size());
  const double each = normal_upper_quantile(0.001 / (2.0 * k));
  const double pooled = normal_upper_quantile(0.0005);
  double sum = 0.0, largest = 0.0;
  for (const Case& c : cases) {
    sum += c.z(scale);
    largest = std::max(largest, std::abs(c.z(scale)));
    if (print) {
      std::printf("%-44s predicted %10.6f mean %10.6f se %8.5f z %7.3f\n", c.name.c_str(),
                  scale * c.predicted_mse, c.mean_mse, c.standard_error, c.z(scale));
    }
  }
  const double bias = sum / std::sqrt(k);
  if (print) {
    std::printf("max |z| %.3f (bound %.3f), sum z / sqrt(k) %.3f (bound %.3f)\n", largest, each,
                bias, pooled);
  }
  return largest < each && std::abs(bias) < pooled;
}

// Each run's trials against its prediction.mse: three distributions (uniform, truncated normal,
// three velocities) in both modes, each run with seeds of its own; 400 trials a run. The same
// runs against prediction.mse x 1.05 fail the rule.
TEST(VelocityDistributionSimulation, MeanMseOfTheTrialsIsThePrediction) {
  constexpr int kTrials = 400;
  if (test::kAddressSanitizer) GTEST_SKIP() << "Monte Carlo: run in the Release suite";
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::pair<std::string, VelocityDistribution>> distributions = {
      {"uniform:0.6:1.4", parsed("uniform:0.6:1.4")},
      {"normal:1:0.15", parsed("normal:1:0.15")},
      {"0.7, 1, 1.3 (0.3, 0.5, 0.2)", three_velocities()}};
  std::vector<Case> cases;
  std::uint64_t seed = 5000;
  for (const auto& [name, distribution] : distributions) {
    for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
      seed += 1000;
      SimulationOptions o = options_under(distribution, mode, seed, kTrials);
      // The aggregated sampler (same mean and variance) keeps the numerical runs cheap.
      if (mode == ShutterMode::kNumerical) o.noise = NoiseModel::kAggregated;
      const SimulationReport r = Simulate(o, camera_strip(), raskar());
      ASSERT_TRUE(r.prediction.finite && r.prediction.mse) << name;
      ASSERT_TRUE(r.trials.mse_mean && r.trials.mse_sd) << name;
      Case c;
      c.name = name + ", " + to_string(mode) + ", seed " + std::to_string(seed);
      c.predicted_mse = *r.prediction.mse;
      c.mean_mse = *r.trials.mse_mean;
      c.standard_error = *r.trials.mse_sd / std::sqrt(static_cast<double>(kTrials));
      cases.push_back(c);
    }
  }
  EXPECT_TRUE(rule_passes(cases, 1.0, true));
  EXPECT_FALSE(rule_passes(cases, 1.05, false)) << "the rule cannot tell a 5% error";
  std::printf("%zu runs of %d trials in %.1f s\n", cases.size(), kTrials,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// --- Reproducibility ---------------------------------------------------------------------------

TEST(VelocityDistributionSimulation, SameResultsForAnyThreadCount) {
  SimulationOptions o = options_under(parsed("normal:1:0.05"), ShutterMode::kNumerical, 11, 3);
  o.threads = 1;
  const SimulationReport one = Simulate(o, small_strip(), raskar());
  o.threads = 2;
  const SimulationReport two = Simulate(o, small_strip(), raskar());
  EXPECT_EQ(one.trial_velocities, two.trial_velocities);
  EXPECT_EQ(one.restored.data, two.restored.data);
  EXPECT_EQ(one.observed.data, two.observed.data);
  EXPECT_EQ(report_json(one, "").dump(), report_json(two, "").dump());
}

TEST(VelocityDistributionSimulation, TrialVelocitiesDependOnTheSeedAndTrialOnly) {
  const VelocityDistribution d = parsed("uniform:0.9:1.1");
  SimulationOptions o = options_under(d, ShutterMode::kAnalog, 21, 5);
  o.noise = NoiseModel::kNone;
  const SimulationReport five = Simulate(o, small_strip(), raskar());
  ASSERT_EQ(five.trial_velocities.size(), 5u);
  for (int t = 0; t < 5; ++t) {
    const double v = five.trial_velocities[static_cast<std::size_t>(t)];
    EXPECT_EQ(v, trial_velocity(d, 21, static_cast<std::uint64_t>(t)));
    EXPECT_TRUE(v >= 0.9 && v <= 1.1) << v;
  }
  EXPECT_EQ(first_trial_velocity(o), five.trial_velocities.front());
  o.trials = 2;
  o.threads = 1;
  const SimulationReport two = Simulate(o, small_strip(), raskar());
  EXPECT_EQ(two.trial_velocities,
            std::vector<double>(five.trial_velocities.begin(), five.trial_velocities.begin() + 2));
  EXPECT_EQ(two.trial_metrics.front().rmse, five.trial_metrics.front().rmse);
  o.seed = 22;
  EXPECT_NE(Simulate(o, small_strip(), raskar()).trial_velocities, two.trial_velocities);
  // Without noise the trials differ by their velocities alone.
  EXPECT_NE(five.trial_metrics[0].rmse, five.trial_metrics[1].rmse);
}

// --- A point distribution is the single-velocity run -------------------------------------------

void expect_same_run(const SimulationReport& single, const SimulationReport& point) {
  EXPECT_EQ(single.geometry.blur_length, point.geometry.blur_length);
  EXPECT_EQ(single.rmse_first, point.rmse_first);
  EXPECT_EQ(single.rmse_end, point.rmse_end);
  EXPECT_EQ(single.observed.data, point.observed.data);
  EXPECT_EQ(single.restored.data, point.restored.data);
  EXPECT_EQ(single.kernel.min_abs, point.kernel.min_abs);
  EXPECT_EQ(single.zero_bins, point.zero_bins);
  ASSERT_EQ(single.trial_metrics.size(), point.trial_metrics.size());
  for (std::size_t t = 0; t < single.trial_metrics.size(); ++t) {
    EXPECT_EQ(single.trial_metrics[t].rmse, point.trial_metrics[t].rmse) << t;
    EXPECT_EQ(single.trial_metrics[t].rmse_ci, point.trial_metrics[t].rmse_ci) << t;
  }
  EXPECT_EQ(single.trials.rmse_mean, point.trials.rmse_mean);
  EXPECT_EQ(single.trials.rmse_sd, point.trials.rmse_sd);
  const Prediction& a = single.prediction;
  const Prediction& b = point.prediction;
  EXPECT_EQ(a.finite, b.finite);
  EXPECT_EQ(a.rmse, b.rmse);
  EXPECT_EQ(a.rmse_noise_free, b.rmse_noise_free);
  EXPECT_EQ(a.noise, b.noise);
  EXPECT_EQ(a.m_amplification, b.m_amplification);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_EQ(a.rmse_stationary, b.rmse_stationary);
  EXPECT_EQ(a.snr_level100, b.snr_level100);
  // What the distribution adds: E[MSE] (its square root is rmse), one evaluation, the trials'
  // MSE statistics and velocities.
  ASSERT_TRUE(b.mse.has_value());
  EXPECT_EQ(std::sqrt(*b.mse), b.rmse);
  EXPECT_EQ(b.mse_evaluations, 1);
  EXPECT_EQ(b.mse_error_estimate, 0.0);
  EXPECT_FALSE(a.mse.has_value());
  EXPECT_TRUE(point.trials.mse_mean.has_value());
  EXPECT_EQ(point.trial_velocities.size(), point.trial_metrics.size());
}

TEST(VelocityDistributionSimulation, PointDistributionIsTheSingleVelocityRun) {
  struct PointCase {
    VelocityDistribution distribution;
    double velocity;
    ShutterMode mode;
    RestorationOptions restoration;
    std::optional<double> restore_velocity;
  };
  VelocityDistribution one_line;
  std::string error;
  ASSERT_TRUE(discrete_velocity_distribution({{0.7, 2.0}}, "v.txt", &one_line, &error)) << error;
  RestorationOptions tikhonov;
  tikhonov.method = RestorationMethod::kTikhonov;
  tikhonov.regularization = 1e-3;
  const std::vector<PointCase> cases = {
      {parsed("uniform:1:1"), 1.0, ShutterMode::kNumerical, {}, std::nullopt},
      {one_line, 0.7, ShutterMode::kAnalog, tikhonov, std::nullopt},
      {parsed("uniform:1:1"), 1.0, ShutterMode::kNumerical, {}, 1.1}};
  for (const PointCase& c : cases) {
    SimulationOptions single = options_under(c.distribution, c.mode, 3, 3);
    single.restoration = c.restoration;
    single.restore_velocity_px_per_slot = c.restore_velocity;
    SimulationOptions point = single;
    single.velocity_distribution.reset();
    single.velocity_px_per_slot = c.velocity;
    SCOPED_TRACE(c.distribution.describe());
    expect_same_run(Simulate(single, camera_strip(), raskar()),
                    Simulate(point, camera_strip(), raskar()));
  }
}

// --- The quadrature ---------------------------------------------------------------------------

// prediction.mse (relative tolerance 1e-4) against the same expectation refined to 1e-6: within
// 1e-4 relative, for a uniform and a truncated normal distribution.
TEST(VelocityDistributionSimulation, QuadratureIsAccurateByRefinement) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "thousands of passes: run in the Release suite";
  for (const std::string spec : {"uniform:0.6:1.4", "normal:1:0.15"}) {
    SimulationOptions o = options_under(parsed(spec), ShutterMode::kNumerical, 1, 1);
    o.noise = NoiseModel::kAggregated;
    const SimulationReport r = Simulate(o, small_strip(), raskar());
    ASSERT_TRUE(r.prediction.mse) << spec;
    const PlanCore plan(o, small_strip().width, raskar());
    std::vector<std::string> warnings;
    const Prediction fine =
        predict_over_velocities(plan, r, small_strip(), raskar(), 1e-6, &warnings, 4096);
    ASSERT_TRUE(fine.mse) << spec;
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    const double relative = std::abs(*r.prediction.mse - *fine.mse) / *fine.mse;
    std::printf("%s: E[MSE] %.10g (%d evaluations), refined %.10g (%d evaluations): %.2g\n",
                spec.c_str(), *r.prediction.mse, r.prediction.mse_evaluations, *fine.mse,
                fine.mse_evaluations, relative);
    EXPECT_LT(relative, 1e-4) << spec;
    EXPECT_LE(r.prediction.mse_error_estimate, 1e-4 * *r.prediction.mse) << spec;
    EXPECT_GT(fine.mse_evaluations, r.prediction.mse_evaluations) << spec;
  }
}

// --- Infinite expectations ---------------------------------------------------------------------

// Three ones: K = 0 at theta = 2 pi / 3, inside the band |theta| <= pi |v| exactly when
// |v| >= 2/3 (dt = 1): invertible at 0.5, not at 1.5.
ShutterCode three_ones() { return {"three ones", {1.0, 1.0, 1.0}}; }

void expect_no_nan(const SimulationReport& r) {
  const Prediction& p = r.prediction;
  for (const double value :
       {p.window_mean, p.q, p.m_amplification, p.rmse_noise_free, p.noise, p.rmse, p.sigma,
        p.rmse_stationary, p.snr_level100, p.mse.value_or(0.0), r.trials.rmse_mean,
        r.trials.rmse_sd, r.trials.mse_mean.value_or(0.0), r.trials.mse_sd.value_or(0.0)}) {
    EXPECT_FALSE(std::isnan(value));
  }
}

TEST(VelocityDistributionSimulation, SupportReachingANonInvertibleVelocityIsInfinite) {
  SimulationOptions o = options_under(parsed("uniform:0.5:1.5"), ShutterMode::kNumerical, 4, 20);
  o.rmse_margin_columns = -1;
  const SimulationReport r = Simulate(o, camera_strip(), three_ones());
  EXPECT_FALSE(r.prediction.finite);
  ASSERT_TRUE(r.prediction.mse);
  EXPECT_TRUE(std::isinf(*r.prediction.mse));
  EXPECT_EQ(r.prediction.mse_infinite_reason, "code not invertible at velocity 1.5 of the support");
  EXPECT_EQ(r.prediction.mse_evaluations, 0);
  expect_no_nan(r);
  const nlohmann::json j = report_json(r, "");
  EXPECT_TRUE(j["prediction"]["mse"].is_null());
  EXPECT_EQ(j["prediction"]["mse_infinite_reason"], r.prediction.mse_infinite_reason);
  EXPECT_NE(r.FullReport().find("predicted E[MSE] infinite: code not invertible at velocity 1.5"),
            std::string::npos)
      << r.FullReport();
  // The trials above 2/3 restore at a kernel that is not invertible, and say how many.
  int beyond = 0;
  for (const double v : r.trial_velocities) beyond += v >= 2.0 / 3.0 ? 1 : 0;
  ASSERT_GT(beyond, 0);
  bool warned = false;
  for (const std::string& w : r.warnings) {
    warned = warned || w.find("is not invertible at the velocity of " + std::to_string(beyond) +
                              " of the 20 trials") != std::string::npos;
  }
  EXPECT_TRUE(warned);

  // Below 2/3 it is finite; a restore velocity beyond makes it infinite again; Tikhonov's
  // filter is bounded over any support.
  o.velocity_distribution = parsed("uniform:0.4:0.6");
  o.trials = 2;
  const SimulationReport below = Simulate(o, camera_strip(), three_ones());
  EXPECT_TRUE(below.prediction.finite);
  EXPECT_TRUE(std::isfinite(below.prediction.mse.value_or(NAN)));
  o.restore_velocity_px_per_slot = 1.5;
  const SimulationReport restored = Simulate(o, camera_strip(), three_ones());
  EXPECT_EQ(restored.prediction.mse_infinite_reason,
            "code not invertible at the restore velocity 1.5");
  expect_no_nan(restored);
  o.restore_velocity_px_per_slot.reset();
  o.velocity_distribution = parsed("uniform:0.5:1.5");
  o.restoration.method = RestorationMethod::kTikhonov;
  o.restoration.regularization = 1e-3;
  const SimulationReport tikhonov = Simulate(o, camera_strip(), three_ones());
  EXPECT_TRUE(tikhonov.prediction.finite);
  EXPECT_TRUE(std::isfinite(tikhonov.prediction.mse.value_or(NAN)));
}

// --- Rules -------------------------------------------------------------------------------------

TEST(VelocityDistributionSimulation, OptionsRefuseWhatCannotRun) {
  SimulationOptions o = options_under(parsed("uniform:0.5:1.5"), ShutterMode::kNumerical, 0, 1);
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.velocity_px_per_slot = 2.0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("velocity_px_per_slot = 2: is the velocity of a run without a distribution"),
            std::string::npos)
      << error;
  o.velocity_px_per_slot = 1.0;
  o.restoration.method = RestorationMethod::kWiener;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("cannot be used with a velocity distribution"), std::string::npos) << error;
  o.restoration.method = RestorationMethod::kTikhonov;
  EXPECT_FALSE(o.IsValid(&error)) << "tikhonov with the optimal lambda";
  o.restoration.regularization = 0.01;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.velocity_distribution->high = 0.0;  // below low
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_EQ(error.rfind("velocity_distribution: ", 0), 0u) << error;
  // A support whose blur does not fit the image, named as the distribution's.
  o.velocity_distribution = parsed("uniform:0:20");
  const std::optional<Error> wide = test::error_of([&] { Simulate(o, camera_strip(), raskar()); });
  ASSERT_TRUE(wide);
  EXPECT_NE(std::string(wide->what()).find("of the velocity distribution's support"),
            std::string::npos)
      << wide->what();
}

// A plan made for one distribution fits it only, and gives Simulate's report.
TEST(VelocityDistributionSimulation, PlanFitsItsDistributionOnly) {
  const SimulationOptions o = options_under(three_velocities(), ShutterMode::kAnalog, 9, 2);
  const SimulationPlan plan(o, small_strip().width, raskar());
  SimulationOptions other = o;
  other.velocity_distribution = parsed("uniform:0.8:1.3");
  EXPECT_FALSE(plan.fits(other, small_strip().width, raskar()));
  other.velocity_distribution.reset();
  EXPECT_FALSE(plan.fits(other, small_strip().width, raskar()));
  other = o;
  other.snr = 30.0;
  other.noise = NoiseModel::kNone;
  EXPECT_TRUE(plan.fits(other, small_strip().width, raskar()));
  EXPECT_EQ(report_json(Simulate(plan, o, small_strip(), raskar()), "").dump(),
            report_json(Simulate(o, small_strip(), raskar()), "").dump());
}

}  // namespace
}  // namespace fss
