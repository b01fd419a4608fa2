// The restorations of docs/method.md §12 through Simulate, deterministic properties: their limits
// (Tikhonov at a vanishing lambda and Wiener without noise are the inverse filter), their
// invariance to the scale of a numerical code, a code the inverse filter cannot invert, what the
// report records, and runs that do not depend on the number of trials or threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/restoration.h"
#include "fss/pipeline/simulate.h"
#include "support/test_util.h"

namespace fss {
namespace {

ShutterCode code(const char* name) { return builtin_code(name).value(); }

// 480 columns (> 9 B, B = 52 at |v| dt <= 1, for the default RMSE window) and 12 rows.
const Image& test_image() {
  static const Image image = test::make_test_image(480, 12, 1, 5);
  return image;
}

RestorationOptions inverse() { return RestorationOptions(); }

RestorationOptions tikhonov(std::optional<double> lambda) {
  RestorationOptions r;
  r.method = RestorationMethod::kTikhonov;
  r.regularization = lambda;
  return r;
}

RestorationOptions wiener(PriorKind prior) {
  RestorationOptions r;
  r.method = RestorationMethod::kWiener;
  r.prior = prior;
  return r;
}

// Every restoration the simulator offers, named.
struct NamedRestoration {
  const char* name;
  RestorationOptions options;
};

std::vector<NamedRestoration> all_restorations() {
  return {{"inverse", inverse()},
          {"tikhonov 1e-3", tikhonov(1e-3)},
          {"tikhonov optimal", tikhonov(std::nullopt)},
          {"wiener power-law", wiener(PriorKind::kPowerLaw)},
          {"wiener oracle", wiener(PriorKind::kOracle)}};
}

SimulationReport run(const RestorationOptions& restoration, const ShutterCode& shutter_code,
                     NoiseModel noise = NoiseModel::kPoisson, const Image& image = test_image()) {
  SimulationOptions options;
  options.restoration = restoration;
  options.noise = noise;
  options.seed = 17;
  options.snr = 50.0;
  return Simulate(options, image, shutter_code);
}

// Tikhonov's filter tends to 1 / K as lambda -> 0, to first order in lambda: at lambda = 1e-8
// the noise-free restoration of raskar is the inverse filter's within 1e-3 gray levels, and the
// difference and that of the predicted RMSE shrink tenfold from lambda = 1e-7 to 1e-8.
TEST(RestorationFilter, TikhonovApproachesTheInverseFilterAsLambdaVanishes) {
  const ShutterCode raskar = code("raskar");
  const SimulationReport reference = run(inverse(), raskar, NoiseModel::kNone);
  const auto distance = [&](double lambda) {
    return test::max_abs_difference(run(tikhonov(lambda), raskar, NoiseModel::kNone).restored,
                                    reference.restored);
  };
  const double at_1e8 = distance(1e-8);
  const double at_1e7 = distance(1e-7);
  EXPECT_GT(at_1e8, 0.0);
  EXPECT_LT(at_1e8, 1e-3);
  EXPECT_NEAR(at_1e7 / at_1e8, 10.0, 0.1);
  // And so does the prediction, with noise.
  const double inverse_rmse = run(inverse(), raskar).prediction.rmse;
  const double gap_1e8 = inverse_rmse - run(tikhonov(1e-8), raskar).prediction.rmse;
  const double gap_1e7 = inverse_rmse - run(tikhonov(1e-7), raskar).prediction.rmse;
  EXPECT_GT(gap_1e8, 0.0);
  EXPECT_LT(gap_1e8, 1e-5 * inverse_rmse);
  EXPECT_NEAR(gap_1e7 / gap_1e8, 10.0, 0.1);
}

// Without noise the oracle's N is 0, so its Wiener filter is conj(K) S / (|K|^2 S) = 1 / K
// wherever S > 0 (every bin of a textured image): the inverse filter's restoration and prediction.
TEST(RestorationFilter, WienerOracleWithoutNoiseIsTheInverseFilter) {
  for (const char* name : {"raskar", "random", "mip"}) {
    const ShutterCode shutter_code = code(name);
    const SimulationReport a = run(inverse(), shutter_code, NoiseModel::kNone);
    const SimulationReport b = run(wiener(PriorKind::kOracle), shutter_code, NoiseModel::kNone);
    EXPECT_LT(test::max_abs_difference(a.restored, b.restored), 1e-9) << name;
    EXPECT_NEAR(b.prediction.rmse, a.prediction.rmse, 1e-9) << name;
    ASSERT_TRUE(b.restoration.noise_variance.has_value()) << name;
    EXPECT_EQ(*b.restoration.noise_variance, 0.0) << name;
  }
}

// A numerical code's gains times 3 multiply K, kappa = dt sum |alpha| and the observation (photon
// noise included: the frames are the same, weighted 3 times as much) by 3: Tikhonov's and
// Wiener's filters (with the prior fitted to the scaled observation) divide by 3, and the
// restoration is the same up to rounding.
TEST(RestorationFilter, DoNotDependOnTheScaleOfANumericalCode) {
  const ShutterCode random = code("random");
  ShutterCode tripled = random;
  tripled.name = "random x 3";
  for (double& gain : tripled.gains) gain *= 3.0;
  for (const NamedRestoration& r : all_restorations()) {
    const SimulationReport a = run(r.options, random);
    const SimulationReport b = run(r.options, tripled);
    EXPECT_LT(test::max_abs_difference(a.restored, b.restored), 1e-9) << r.name;
    EXPECT_NEAR(b.metrics.rmse, a.metrics.rmse, 1e-9 * a.metrics.rmse) << r.name;
    EXPECT_NEAR(b.prediction.rmse, a.prediction.rmse, 1e-9 * a.prediction.rmse) << r.name;
    if (a.restoration.regularization) {
      ASSERT_TRUE(b.restoration.regularization.has_value()) << r.name;
      EXPECT_NEAR(*b.restoration.regularization, *a.restoration.regularization,
                  1e-9 * *a.restoration.regularization)
          << r.name;
    }
    if (a.restoration.prior_level) {
      ASSERT_TRUE(b.restoration.prior_level.has_value()) << r.name;
      EXPECT_NEAR(*b.restoration.prior_level, *a.restoration.prior_level,
                  1e-9 * *a.restoration.prior_level)
          << r.name;
    }
  }
}

// The accumulation code's K vanishes on the grid at v = 1: the inverse filter has no finite
// prediction, Tikhonov's and Wiener's filters are bounded and theirs is finite.
TEST(RestorationFilter, RegularizedOnesPredictANonInvertibleCode) {
  const ShutterCode accumulation = code("accumulation");
  for (const NamedRestoration& r : all_restorations()) {
    const SimulationReport report = run(r.options, accumulation);
    EXPECT_FALSE(report.kernel.invertible) << r.name;
    EXPECT_GT(report.zero_bins, 0) << r.name;
    if (r.options.method == RestorationMethod::kInverse) {
      EXPECT_FALSE(report.prediction.finite) << r.name;
      EXPECT_TRUE(std::isinf(report.prediction.rmse)) << r.name;
    } else {
      EXPECT_TRUE(report.prediction.finite) << r.name;
      EXPECT_TRUE(std::isfinite(report.prediction.rmse)) << r.name;
      EXPECT_GT(report.prediction.rmse, 0.0) << r.name;
    }
  }
}

// The power-law prior's noise comes from the mean level, mean(observed) / K(0): a code of zero
// sum observes none, and is refused with the prior that needs it (the oracle prior is not).
TEST(RestorationFilter, PowerLawPriorRefusesACodeOfZeroSum) {
  const ShutterCode zero_sum{"zero sum", {1.0, -1.0, 0.5, -0.5}};
  RestorationOptions power_law;
  power_law.method = RestorationMethod::kWiener;
  EXPECT_TRUE(test::throws_error([&] { run(power_law, zero_sum); }, ErrorKind::kUsage,
                                 {"gains of zero sum"}));
  RestorationOptions oracle = power_law;
  oracle.prior = PriorKind::kOracle;
  EXPECT_TRUE(std::isfinite(run(oracle, zero_sum).prediction.rmse));
}

// report.restoration: the options as asked, and the lambda, prior level and noise variance
// applied, each only for the restoration that has it.
TEST(RestorationFilter, ReportRecordsTheFilterApplied) {
  const ShutterCode raskar = code("raskar");
  const SimulationReport plain = run(inverse(), raskar);
  EXPECT_EQ(plain.restoration.options.method, RestorationMethod::kInverse);
  EXPECT_FALSE(plain.restoration.regularization.has_value());
  EXPECT_FALSE(plain.restoration.prior_level.has_value());
  EXPECT_FALSE(plain.restoration.noise_variance.has_value());

  const SimulationReport fixed = run(tikhonov(1e-3), raskar);
  EXPECT_EQ(fixed.restoration.options.method, RestorationMethod::kTikhonov);
  ASSERT_TRUE(fixed.restoration.regularization.has_value());
  EXPECT_EQ(*fixed.restoration.regularization, 1e-3);
  EXPECT_FALSE(fixed.restoration.prior_level.has_value());

  const SimulationReport optimal = run(tikhonov(std::nullopt), raskar);
  EXPECT_FALSE(optimal.restoration.options.regularization.has_value());
  ASSERT_TRUE(optimal.restoration.regularization.has_value());
  const double lambda = *optimal.restoration.regularization;
  EXPECT_GE(lambda, kMinRegularization);
  EXPECT_LE(lambda, kMaxRegularization);
  // It minimises the exact expected error: no lambda of a grid over the range does better
  // (beyond the search's tolerance), and the fixed lambda of its report gives the same run.
  for (int exponent = -8; exponent <= 2; ++exponent) {
    const double grid =
        std::clamp(std::pow(10.0, exponent), kMinRegularization, kMaxRegularization);
    const double rmse = run(tikhonov(grid), raskar).prediction.rmse;
    EXPECT_LE(optimal.prediction.rmse, rmse * (1.0 + 1e-9)) << "lambda " << grid;
  }
  const SimulationReport replay = run(tikhonov(lambda), raskar);
  EXPECT_EQ(replay.restored.data, optimal.restored.data);
  EXPECT_EQ(replay.prediction.rmse, optimal.prediction.rmse);

  const SimulationReport power_law = run(wiener(PriorKind::kPowerLaw), raskar);
  EXPECT_EQ(power_law.restoration.options.prior, PriorKind::kPowerLaw);
  EXPECT_FALSE(power_law.restoration.regularization.has_value());
  ASSERT_TRUE(power_law.restoration.prior_level.has_value());
  ASSERT_TRUE(power_law.restoration.noise_variance.has_value());
  EXPECT_GT(*power_law.restoration.prior_level, 0.0);
  EXPECT_GT(*power_law.restoration.noise_variance, 0.0);
  EXPECT_TRUE(std::isfinite(*power_law.restoration.prior_level));

  const SimulationReport oracle = run(wiener(PriorKind::kOracle), raskar);
  EXPECT_EQ(oracle.restoration.options.prior, PriorKind::kOracle);
  EXPECT_FALSE(oracle.restoration.prior_level.has_value());
  ASSERT_TRUE(oracle.restoration.noise_variance.has_value());
  EXPECT_GT(*oracle.restoration.noise_variance, 0.0);
}

// Options of a run with noise whose number of trials or threads changes.
SimulationOptions noisy_options(const RestorationOptions& restoration, ShutterMode mode) {
  SimulationOptions options;
  options.mode = mode;
  options.restoration = restoration;
  options.seed = 41;
  options.snr = 30.0;
  options.velocity_px_per_slot = 0.6;
  options.sensor.read_noise_electrons = 4.0;
  return options;
}

// Every filter is fitted once per run, from the image and (power-law prior) a calibration
// observation on streams of its own, never the trials': the first trial is the same whatever
// the number of trials, filter and figures included, and its observation is the one every
// restoration of the same seed sees.
TEST(RestorationFilter, FirstTrialDoesNotDependOnTheNumberOfTrials) {
  const ShutterCode raskar = code("raskar");
  const SimulationReport plain =
      Simulate(noisy_options(inverse(), ShutterMode::kNumerical), test_image(), raskar);
  for (const NamedRestoration& r : all_restorations()) {
    SimulationOptions options = noisy_options(r.options, ShutterMode::kNumerical);
    options.trials = 1;
    const SimulationReport one = Simulate(options, test_image(), raskar);
    EXPECT_EQ(one.observed.data, plain.observed.data) << r.name;
    options.trials = 3;
    const SimulationReport three = Simulate(options, test_image(), raskar);
    ASSERT_EQ(three.trial_metrics.size(), 3u) << r.name;
    EXPECT_EQ(one.trial_metrics[0].rmse, three.trial_metrics[0].rmse) << r.name;
    EXPECT_EQ(one.trial_metrics[0].rmse_ci, three.trial_metrics[0].rmse_ci) << r.name;
    EXPECT_EQ(one.trial_metrics[0].ssim, three.trial_metrics[0].ssim) << r.name;
    EXPECT_EQ(one.restored.data, three.restored.data) << r.name;
    EXPECT_EQ(one.prediction.rmse, three.prediction.rmse) << r.name;
    EXPECT_EQ(one.restoration.regularization, three.restoration.regularization) << r.name;
    EXPECT_EQ(one.restoration.prior_level, three.restoration.prior_level) << r.name;
    EXPECT_EQ(one.restoration.noise_variance, three.restoration.noise_variance) << r.name;
    // The later trials do differ from the first.
    EXPECT_NE(three.trial_metrics[1].rmse, three.trial_metrics[0].rmse) << r.name;
  }
}

// The power-law prior's calibration observation is drawn with the run's seed: another seed
// fits another prior level.
TEST(RestorationFilter, PowerLawPriorFollowsTheSeed) {
  SimulationOptions options = noisy_options(wiener(PriorKind::kPowerLaw), ShutterMode::kNumerical);
  const SimulationReport a = Simulate(options, test_image(), code("raskar"));
  options.seed += 1;
  const SimulationReport b = Simulate(options, test_image(), code("raskar"));
  EXPECT_NE(a.restoration.prior_level, b.restoration.prior_level);
}

// The number of threads never changes a byte of a run, for each restoration and both modes, on
// a colour image with enough rows for several blocks.
TEST(RestorationFilter, ThreadCountNeverChangesTheBytes) {
  const Image image = test::make_test_image(480, 40, 3, 8);
  const ShutterCode raskar = code("raskar");
  for (const NamedRestoration& r : all_restorations()) {
    for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
      SimulationOptions options = noisy_options(r.options, mode);
      options.trials = 2;
      options.threads = 1;
      const SimulationReport one = Simulate(options, image, raskar);
      options.threads = 2;
      const SimulationReport two = Simulate(options, image, raskar);
      const std::string what = std::string(r.name) + ", " + to_string(mode);
      EXPECT_EQ(one.restored.data, two.restored.data) << what;
      EXPECT_EQ(one.observed.data, two.observed.data) << what;
      ASSERT_EQ(one.trial_metrics.size(), two.trial_metrics.size()) << what;
      for (std::size_t t = 0; t < one.trial_metrics.size(); ++t) {
        EXPECT_EQ(one.trial_metrics[t].rmse, two.trial_metrics[t].rmse) << what;
        EXPECT_EQ(one.trial_metrics[t].rmse_ci, two.trial_metrics[t].rmse_ci) << what;
        EXPECT_EQ(one.trial_metrics[t].ssim, two.trial_metrics[t].ssim) << what;
      }
      EXPECT_EQ(one.prediction.rmse, two.prediction.rmse) << what;
      EXPECT_EQ(one.prediction.rmse_stationary, two.prediction.rmse_stationary) << what;
      EXPECT_EQ(one.prediction.m_amplification, two.prediction.m_amplification) << what;
      EXPECT_EQ(one.restoration.regularization, two.restoration.regularization) << what;
      EXPECT_EQ(one.restoration.prior_level, two.restoration.prior_level) << what;
      EXPECT_EQ(one.restoration.noise_variance, two.restoration.noise_variance) << what;
    }
  }
}

}  // namespace
}  // namespace fss
