// Code design under a restoration prior (docs/method.md §12): the Wiener and Tikhonov figures of
// merit against the inverse filter's where they must reduce to it, their scale invariance, the
// optimizer's objective and its gradient against central differences, and the optimizer under
// them against the paper's codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "design/restoration_figure.h"
#include "fss/core/error.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/model/code.h"
#include "fss/model/restoration.h"
#include "fss/model/sensor.h"
#include "support/test_util.h"

namespace fss {
namespace {

using design_detail::RestorationObjective;
using test::throws_error;

std::vector<double> paper(const std::string& name) { return test::paper_gains(name); }

RestorationOptions wiener(double gamma = 2.0, std::optional<double> level = std::nullopt) {
  RestorationOptions r;
  r.method = RestorationMethod::kWiener;
  r.prior_exponent = gamma;
  r.prior_level = level;
  return r;
}

RestorationOptions tikhonov(std::optional<double> lambda = std::nullopt) {
  RestorationOptions r;
  r.method = RestorationMethod::kTikhonov;
  r.regularization = lambda;
  return r;
}

// E of `gains` at v = 1, dt = 1, snr 100, numerical mode.
double error_of(const std::vector<double>& gains, const RestorationOptions& r,
                ShutterMode mode = ShutterMode::kNumerical, double snr = 100.0,
                const SensorModel& sensor = {}) {
  return level100_restoration_error(gains, 1.0, 1.0, snr, mode, r, sensor).error;
}

// ---------------------------------------------------------------------------
// Reductions.

TEST(RestorationFigure, InverseIsTheSnrAtLevel100OfTheAnalysis) {
  for (const std::string name : {"raskar", "mip", "sinc", "snapshot"}) {
    const CodeAnalysis a =
        analyze_code({name, paper(name)}, 1.0, 1.0, 100.0, ShutterMode::kNumerical);
    EXPECT_NEAR(100.0 / std::sqrt(error_of(paper(name), {})), a.snr_level100,
                1e-12 * a.snr_level100)
        << name;
    EXPECT_NEAR(a.restoration_error, error_of(paper(name), {}), 1e-12 * a.restoration_error);
  }
  EXPECT_TRUE(std::isinf(error_of(paper("accumulation"), {})));
}

TEST(RestorationFigure, WienerWithAHugePriorIsTheInverseFilter) {
  // S -> infinity: e = V / (|K|^2 + V / S) -> V / |K|^2.
  for (const std::string name : {"raskar", "random", "sinc"}) {
    const double inverse = error_of(paper(name), {});
    for (const double gamma : {0.0, 2.0, 4.0}) {
      const double huge = error_of(paper(name), wiener(gamma, 1e100));
      EXPECT_NEAR(huge, inverse, 1e-9 * inverse) << name << " gamma " << gamma;
      // A finite prior always lowers the error.
      EXPECT_LT(error_of(paper(name), wiener(gamma, 180.0)), inverse) << name;
    }
  }
}

TEST(RestorationFigure, TikhonovAtTheSmallestLambdaIsCloseToTheInverseFilter) {
  const std::vector<double> raskar = paper("raskar");
  const double inverse = error_of(raskar, {});
  const RestorationError small = level100_restoration_error(
      raskar, 1.0, 1.0, 100.0, ShutterMode::kNumerical, tikhonov(kMinRegularization));
  EXPECT_EQ(small.regularization, kMinRegularization);
  // mu = 1e-8 * 26^2 against min |K|^2 = 0.95: a relative change of about 1e-5.
  EXPECT_NEAR(small.error, inverse, 1e-4 * inverse);
  EXPECT_NE(small.error, inverse);
  // A large lambda trades noise for bias: far from the inverse filter.
  EXPECT_GT(std::abs(error_of(raskar, tikhonov(1.0)) - inverse), 0.1 * inverse);
}

TEST(RestorationFigure, OptimalLambdaMinimisesTheError) {
  for (const std::string name : {"raskar", "mip", "snapshot"}) {
    for (const double snr : {5.0, 100.0}) {
      const RestorationError best = level100_restoration_error(paper(name), 1.0, 1.0, snr,
                                                               ShutterMode::kNumerical, tikhonov());
      ASSERT_GE(best.regularization, kMinRegularization);
      ASSERT_LE(best.regularization, kMaxRegularization);
      for (double lambda = kMinRegularization; lambda <= kMaxRegularization; lambda *= 3.0) {
        EXPECT_LE(best.error, error_of(paper(name), tikhonov(lambda), ShutterMode::kNumerical, snr))
            << name << " snr " << snr << " lambda " << lambda;
      }
      for (const double factor : {0.999, 1.001}) {
        const double nearby =
            std::clamp(best.regularization * factor, kMinRegularization, kMaxRegularization);
        EXPECT_LE(best.error * (1.0 - 1e-12),
                  error_of(paper(name), tikhonov(nearby), ShutterMode::kNumerical, snr));
      }
    }
  }
}

TEST(RestorationFigure, TheAccumulationCodeHasAFiniteFigure) {
  const ShutterCode accumulation{"accumulation", paper("accumulation")};
  for (const RestorationOptions& r : {wiener(), wiener(1.0, 50.0), tikhonov(), tikhonov(1e-3)}) {
    for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
      const CodeAnalysis a = analyze_code(accumulation, 1.0, 1.0, 100.0, mode, 0, SensorModel{}, r);
      EXPECT_FALSE(a.invertible);
      EXPECT_TRUE(std::isinf(a.m));
      EXPECT_TRUE(std::isfinite(a.restoration_error)) << describe(r);
      EXPECT_GT(a.snr_level100, 0.0) << describe(r);
      EXPECT_TRUE(std::isfinite(a.snr_level100)) << describe(r);
      EXPECT_TRUE(std::isinf(a.snr_level100_bound));  // the bound is the inverse filter's
    }
  }
  const CodeAnalysis inverse = analyze_code(accumulation, 1.0, 1.0, 100.0, ShutterMode::kNumerical);
  EXPECT_EQ(inverse.snr_level100, 0.0);
}

// A numerical code of zero sum has K(0) = 0: it loses the mean level, whose prior power
// c |xi|^-gamma is not integrable for gamma >= 1, so E is infinite (SNR 0) whatever the nodes
// see; for gamma < 1 it is finite.
TEST(RestorationFigure, ACodeOfZeroSumLosesTheMeanLevel) {
  const ShutterCode zero_sum{"zero sum", {1.0, -1.0, 0.5, -0.5}};
  for (const RestorationOptions& r : {wiener(), wiener(1.0, 50.0), tikhonov(), tikhonov(1e-3)}) {
    const CodeAnalysis a =
        analyze_code(zero_sum, 1.0, 1.0, 100.0, ShutterMode::kNumerical, 0, SensorModel{}, r);
    EXPECT_TRUE(std::isinf(a.restoration_error)) << describe(r);
    EXPECT_EQ(a.snr_level100, 0.0) << describe(r);
  }
  const CodeAnalysis integrable = analyze_code(zero_sum, 1.0, 1.0, 100.0, ShutterMode::kNumerical,
                                               0, SensorModel{}, wiener(0.5, 180.0));
  EXPECT_TRUE(std::isfinite(integrable.restoration_error));
  EXPECT_GT(integrable.snr_level100, 0.0);
}

// ---------------------------------------------------------------------------
// Scale invariance: V ~ s^2, |K|^2 ~ s^2 (and mu ~ s^2) in the numerical mode.

TEST(RestorationFigure, NumericalCodesKeepTheirErrorWhenScaled) {
  SensorModel sensor;
  sensor.read_noise_electrons = 3.0;
  sensor.dark_current_electrons_per_slot = 0.5;
  for (const std::string name : {"raskar", "mip", "accumulation"}) {
    for (const RestorationOptions& r : {wiener(), wiener(3.0, 1e4), tikhonov(), tikhonov(0.01)}) {
      for (const SensorModel& s : {SensorModel{}, sensor}) {
        const double e = error_of(paper(name), r, ShutterMode::kNumerical, 20.0, s);
        for (const double scale : {1e-3, -2.0, 7.0}) {
          std::vector<double> scaled = paper(name);
          for (double& g : scaled) g *= scale;
          EXPECT_NEAR(error_of(scaled, r, ShutterMode::kNumerical, 20.0, s), e, 1e-10 * e)
              << name << " " << describe(r) << " scale " << scale;
        }
      }
    }
  }
}

TEST(RestorationFigure, AnalogCodesGainByBeingScaledUp) {
  // V ~ s (one exposure), |K|^2 ~ s^2: the error falls as s grows.
  for (const RestorationOptions& r : {wiener(), tikhonov(), tikhonov(0.01)}) {
    std::vector<double> half = paper("raskar");
    for (double& g : half) g *= 0.5;
    EXPECT_LT(error_of(paper("raskar"), r, ShutterMode::kAnalog),
              error_of(half, r, ShutterMode::kAnalog))
        << describe(r);
  }
}

// ---------------------------------------------------------------------------
// The optimizer's objective.

TEST(RestorationObjective, EqualsTheErrorOfTheAnalysisOnItsGrid) {
  SensorModel sensor;
  sensor.read_noise_electrons = 4.0;
  for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
    for (const RestorationOptions& r : {wiener(), wiener(1.5, 30.0), tikhonov(), tikhonov(1e-3)}) {
      const double snr = 10.0;
      const double c = readout_noise_slots(sensor, 52, 1.0, mode, snr);
      const RestorationObjective objective(52, 1.0, 1.0, mode, snr, r, kBandGridPoints, c);
      const RestorationError expected =
          level100_restoration_error(paper("raskar"), 1.0, 1.0, snr, mode, r, sensor);
      double lambda = -1.0;
      const double value = objective.Evaluate(paper("raskar"), {}, &lambda);
      EXPECT_NEAR(value, expected.error, 1e-9 * expected.error) << describe(r);
      EXPECT_NEAR(lambda, expected.regularization, 1e-6 * expected.regularization);
    }
  }
}

class RestorationGradient
    : public ::testing::TestWithParam<std::tuple<ShutterMode, int /* restoration */>> {};

RestorationOptions gradient_case(int which) {
  switch (which) {
    case 0:
      return wiener();
    case 1:
      return wiener(1.3, 40.0);
    case 2:
      return tikhonov(2e-3);
    default:
      return tikhonov();
  }
}

TEST_P(RestorationGradient, MatchesCentralDifferences) {
  const auto [mode, which] = GetParam();
  const RestorationOptions r = gradient_case(which);
  const int length = 17;
  const RestorationObjective objective(length, 0.9, 1.0, mode, 8.0, r, 512, 0.3);
  for (int trial = 0; trial < 2; ++trial) {
    std::vector<double> gains =
        generate_random_code(length, 70 + trial, mode == ShutterMode::kAnalog);
    // Away from 0 (the kink of |alpha| in kappa) and inside (0, 1) for analog gains.
    for (double& g : gains) g = g >= 0.0 ? 0.15 + 0.7 * g : -0.15 + 0.7 * g;
    std::vector<double> gradient(length);
    const double value = objective.Evaluate(gains, gradient);
    ASSERT_TRUE(std::isfinite(value));
    double largest = 0.0;
    for (const double d : gradient) largest = std::max(largest, std::abs(d));
    ASSERT_GT(largest, 0.0);
    for (int k = 0; k < length; ++k) {
      const double h = 1e-5;
      std::vector<double> plus = gains, minus = gains;
      plus[k] += h;
      minus[k] -= h;
      const double numeric = (objective.Evaluate(plus) - objective.Evaluate(minus)) / (2.0 * h);
      EXPECT_NEAR(gradient[k], numeric, 1e-6 * largest + 1e-9 * value) << describe(r) << " k " << k;
    }
  }
}

std::string gradient_case_name(const ::testing::TestParamInfo<std::tuple<ShutterMode, int>>& info) {
  static const char* const kNames[] = {"Wiener", "WienerGamma13", "TikhonovFixed",
                                       "TikhonovOptimal"};
  const bool numerical = std::get<0>(info.param) == ShutterMode::kNumerical;
  return std::string(numerical ? "Numerical" : "Analog") + kNames[std::get<1>(info.param)];
}

INSTANTIATE_TEST_SUITE_P(Restorations, RestorationGradient,
                         ::testing::Combine(::testing::Values(ShutterMode::kNumerical,
                                                              ShutterMode::kAnalog),
                                            ::testing::Values(0, 1, 2, 3)),
                         gradient_case_name);

// ---------------------------------------------------------------------------
// The optimizer under a restoration.

OptimizeOptions quick(ShutterMode mode, const RestorationOptions& r, double snr) {
  OptimizeOptions o;
  o.mode = mode;
  o.restoration = r;
  o.snr = snr;
  o.restarts = 2;
  o.max_iterations = 150;
  return o;
}

TEST(RestorationOptimize, WienerOptimumBeatsTheAdmissiblePaperCodes) {
  for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
    for (const double snr : {5.0, 100.0}) {
      const OptimizationResult result = optimize_code(quick(mode, wiener(), snr));
      const double ours = result.analysis.snr_level100;
      EXPECT_EQ(result.analysis.restoration.method, RestorationMethod::kWiener);
      for (const std::string name : {"raskar", "snapshot", "accumulation"}) {
        const CodeAnalysis paper_code =
            analyze_code({name, paper(name)}, 1.0, 1.0, snr, mode, 0, SensorModel{}, wiener());
        EXPECT_GE(ours, paper_code.snr_level100) << name << " snr " << snr;
      }
      // Strictly better than raskar, by a margin.
      const CodeAnalysis raskar = analyze_code({"raskar", paper("raskar")}, 1.0, 1.0, snr, mode, 0,
                                               SensorModel{}, wiener());
      EXPECT_GT(ours, 1.05 * raskar.snr_level100) << "snr " << snr;
    }
  }
}

TEST(RestorationOptimize, AtLowSnrTheBestBoxIsAStartAndIsBeaten) {
  // At snr 5 a Wiener restoration pays for light: the optimum is better than the snapshot, and
  // at least as good as every box code of n ones.
  const OptimizationResult result = optimize_code(quick(ShutterMode::kAnalog, wiener(), 5.0));
  EXPECT_GT(result.analysis.ratio_to_snapshot, 1.1);
  for (int n = 1; n <= 52; ++n) {
    std::vector<double> box(52, 0.0);
    std::fill(box.begin(), box.begin() + n, 1.0);
    EXPECT_GE(result.analysis.snr_level100,
              100.0 / std::sqrt(error_of(box, wiener(), ShutterMode::kAnalog, 5.0)) * (1 - 1e-6))
        << n;
  }
}

TEST(RestorationOptimize, TikhonovAndBinaryBeatRaskar) {
  OptimizeOptions binary = quick(ShutterMode::kNumerical, wiener(), 20.0);
  binary.binary = true;
  binary.min_light_slots = 26;
  binary.max_iterations = 40;
  const OptimizationResult b = optimize_code(binary);
  const double raskar_wiener = analyze_code({"raskar", paper("raskar")}, 1.0, 1.0, 20.0,
                                            ShutterMode::kNumerical, 0, SensorModel{}, wiener())
                                   .snr_level100;
  EXPECT_GE(gain_sum(b.gains), 26.0);
  EXPECT_GE(b.analysis.snr_level100, raskar_wiener);

  const OptimizationResult t = optimize_code(quick(ShutterMode::kAnalog, tikhonov(), 20.0));
  const CodeAnalysis raskar = analyze_code({"raskar", paper("raskar")}, 1.0, 1.0, 20.0,
                                           ShutterMode::kAnalog, 0, SensorModel{}, tikhonov());
  EXPECT_GT(t.analysis.snr_level100, raskar.snr_level100);
  EXPECT_GT(t.analysis.regularization, 0.0);
  EXPECT_NE(t.FullReport().find("Regularization: lambda"), std::string::npos);
}

TEST(RestorationOptimize, OptionsAndAnalysisRefuseWhatDesignCannotUse) {
  OptimizeOptions o;
  o.restoration = wiener();
  o.restoration.prior = PriorKind::kOracle;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("oracle"), std::string::npos) << error;
  o.restoration = wiener();
  o.restoration.regularization = 0.1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("regularization"), std::string::npos) << error;
  o.restoration = tikhonov(1e3);
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("regularization"), std::string::npos) << error;

  const ShutterCode raskar{"raskar", paper("raskar")};
  EXPECT_TRUE(throws_error(
      [&] { analyze_code(raskar, 1.0, 1.0, 100.0, ShutterMode::kNumerical, 920, {}, wiener()); },
      ErrorKind::kUsage, {"grid 920"}));
  RestorationOptions oracle = wiener();
  oracle.prior = PriorKind::kOracle;
  EXPECT_TRUE(throws_error(
      [&] { analyze_code(raskar, 1.0, 1.0, 100.0, ShutterMode::kNumerical, 0, {}, oracle); },
      ErrorKind::kUsage, {"oracle"}));
  EXPECT_TRUE(throws_error([&] { error_of(paper("raskar"), wiener(9.0)); }, ErrorKind::kUsage,
                           {"prior_exponent"}));
}

}  // namespace
}  // namespace fss
