// The sensor model in the simulation (docs/method.md §10): a default sensor
// leaves every output as the photon-noise simulator gave it; the exact
// prediction with read noise, dark current and an ADC is the mean of many
// trials in both modes; clipping is detected, warned about and marks the
// prediction approximate; the results do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "campaign/sha256.h"
#include "fss/core/error.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/simulate.h"
#include "support/test_util.h"

namespace fss {
namespace {

// SHA-256 of a run's observed and restored images and of its predicted and
// measured RMSE, each value rounded to a float: the last bits of a double
// follow FFTW's processor-dependent codelets, a float's do not (but for a
// value within 2^-24 of a float boundary).
std::string digest(const SimulationReport& r) {
  Sha256 hash;
  const auto add = [&](const std::vector<float>& values) {
    hash.update(std::string_view(reinterpret_cast<const char*>(values.data()),
                                 values.size() * sizeof(float)));
  };
  add(std::vector<float>(r.observed.data.begin(), r.observed.data.end()));
  add(std::vector<float>(r.restored.data.begin(), r.restored.data.end()));
  add({static_cast<float>(r.prediction.rmse), static_cast<float>(r.prediction.rmse_stationary),
       static_cast<float>(r.trials.rmse_mean)});
  std::string hex;
  for (const std::uint8_t byte : hash.finish()) {
    char text[3];
    std::snprintf(text, sizeof text, "%02x", byte);
    hex += text;
  }
  return hex;
}

// The run's warnings but SSIM's note that no pixel is left for it (these
// strips are lower than its 11 x 11 window, or have no margin).
std::vector<std::string> warnings_but_ssim(const SimulationReport& r) {
  std::vector<std::string> kept;
  for (const std::string& w : r.warnings) {
    if (w.rfind("SSIM is null", 0) != 0) kept.push_back(w);
  }
  return kept;
}

// The digests of three runs computed with the photon-noise simulator before
// the sensor model existed (the library of commit a55db8f): a default
// SensorModel must reproduce them.
TEST(DefaultSensor, ReproducesThePhotonNoiseSimulatorsOutputs) {
  const Image input = test::make_test_image(480, 6, 3, 7);
  SimulationOptions numerical;
  numerical.trials = 2;
  numerical.seed = 11;
  EXPECT_EQ(digest(Simulate(numerical, input, *builtin_code("raskar"))),
            "6c67a7dbf768d1f2b2e7e113a9e19e3e19d0708b127c5da496b9de3e828676be");
  SimulationOptions analog;
  analog.mode = ShutterMode::kAnalog;
  analog.velocity_px_per_slot = 0.7;
  analog.snr = 40.0;
  EXPECT_EQ(digest(Simulate(analog, input, *builtin_code("raskar"))),
            "83e6e2dc2818d89acf7c962d8e24c3aa995349dbc6766f47577db03c919a2fee");
  SimulationOptions aggregated;
  aggregated.velocity_px_per_slot = 0.37;
  aggregated.noise = NoiseModel::kAggregated;
  aggregated.trials = 3;
  aggregated.snr = 200.0;
  EXPECT_EQ(digest(Simulate(aggregated, input, *builtin_code("random"))),
            "0c5d9a4ab420aaf1c50794ce42c5285874728e949a958adc0f1f03b3d4f08e07");
}

TEST(DefaultSensor, ReportHasNoWarningAndAnExactPrediction) {
  const SimulationReport r =
      Simulate(SimulationOptions(), test::make_test_image(480, 4, 1), *builtin_code("raskar"));
  EXPECT_TRUE(warnings_but_ssim(r).empty());
  EXPECT_TRUE(r.prediction.exact);
  EXPECT_FALSE(r.options.sensor.enabled());
}

// --- options ----------------------------------------------------------------

TEST(SensorOptions, InvalidSensorIsNamedAsAnOptionsField) {
  SimulationOptions options;
  options.sensor.read_noise_electrons = -2.0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_EQ(error, "sensor.read_noise_electrons = -2: must be finite and >= 0");
  EXPECT_TRUE(test::throws_error(
      [&] { Simulate(options, test::make_test_image(480, 4, 1), *builtin_code("raskar")); },
      ErrorKind::kUsage, {"sensor.read_noise_electrons = -2"}));
}

TEST(SensorOptions, AggregatedNoiseTakesReadNoiseAndDarkCurrentButNoClipping) {
  SimulationOptions options;
  options.noise = NoiseModel::kAggregated;
  options.sensor.read_noise_electrons = 3.0;
  options.sensor.dark_current_electrons_per_slot = 1.0;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  for (const bool full_well : {true, false}) {
    SimulationOptions clipping = options;
    if (full_well) {
      clipping.sensor.full_well_electrons = 1e5;
    } else {
      clipping.sensor.adc_bits = 12;
    }
    EXPECT_FALSE(clipping.IsValid(&error));
    EXPECT_EQ(error,
              "noise = aggregated: must be poisson or none with a full well or an ADC (the "
              "aggregated noise does not draw each frame's charge)");
  }
}

// --- the exact prediction ----------------------------------------------------

const std::vector<double> kAnalogGains = {1.0, 0.3, 0.8, 0.0, 0.6, 1.0, 0.2, 0.9};
const std::vector<double> kRealGains = {1.0, -0.4, 0.7, 0.5, -0.2, 0.9, 0.3, 0.6};

// A small image whose readouts stay clear of 0 (the ADC would clip there):
// the test image lifted by 40 gray levels.
Image lifted_image(int width, int height) {
  Image image = test::make_test_image(width, height, 1, 13);
  for (double& v : image.data) v += 40.0;
  return image;
}

// read noise 8 e-, dark current 2 e- a slot, a 12-bit ADC of 2 e- a count,
// at snr 10 (one electron per gray level and slot): the readouts' variance
// is a large part of the noise.
SensorModel test_sensor() {
  SensorModel s;
  s.read_noise_electrons = 8.0;
  s.dark_current_electrons_per_slot = 2.0;
  s.adc_bits = 12;
  s.adc_gain_electrons_per_count = 2.0;
  return s;
}

// sqrt(E[MSE]) from the trials, as the mean of their MSE, and its standard
// error; z of the prediction.
double z_score(const SimulationReport& r) {
  const TrialStatistics& t = r.trials;
  const double n = t.n;
  const double mean_mse = t.rmse_mean * t.rmse_mean + t.rmse_sd * t.rmse_sd * (n - 1.0) / n;
  const double measured = std::sqrt(mean_mse);
  const double standard_error = t.rmse_sd / std::sqrt(n);
  std::printf("  %s %s: predicted %.6f, measured %.6f +- %.6f, z = %+.2f\n",
              to_string(r.options.mode).c_str(), to_string(r.options.noise).c_str(),
              r.prediction.rmse, measured, standard_error,
              (r.prediction.rmse - measured) / standard_error);
  return (r.prediction.rmse - measured) / standard_error;
}

struct SensorCase {
  const char* name;
  ShutterMode mode;
  NoiseModel noise;
  bool adc;
};

class SensorPrediction : public ::testing::TestWithParam<SensorCase> {};

TEST_P(SensorPrediction, IsTheMeanOfManyTrialsWithinThreeStandardErrors) {
  // A statistical check of 600 trials: the Release suite's; the sanitizers see the same code in
  // the other tests of this file.
  if (test::kAddressSanitizer) GTEST_SKIP() << "Monte Carlo: run in the Release suite";
  const SensorCase& c = GetParam();
  SimulationOptions options;
  options.mode = c.mode;
  options.noise = c.noise;
  options.snr = 10.0;
  options.rmse_margin_columns = 0;
  options.trials = 600;  // a standard error of 0.16% of the RMSE
  options.seed = 20000;
  options.sensor = test_sensor();
  if (!c.adc) options.sensor.adc_bits = 0;
  const ShutterCode code{"short", c.mode == ShutterMode::kAnalog ? kAnalogGains : kRealGains};
  const Image input = lifted_image(96, 24);
  const SimulationReport r = Simulate(options, input, code);
  ASSERT_TRUE(r.prediction.finite);
  EXPECT_TRUE(r.prediction.exact) << c.name;
  EXPECT_TRUE(warnings_but_ssim(r).empty()) << c.name << ": " << warnings_but_ssim(r).front();
  EXPECT_LT(std::abs(z_score(r)), 3.0) << c.name;
  // The readouts are a visible part of the prediction: without them it is
  // more than 3 standard errors lower.
  SimulationOptions photon_only = options;
  photon_only.sensor = SensorModel();
  photon_only.trials = 1;
  const SimulationReport p = Simulate(photon_only, input, code);
  EXPECT_GT(r.prediction.rmse - p.prediction.rmse,
            3.0 * r.trials.rmse_sd / std::sqrt(static_cast<double>(r.trials.n)))
      << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    ReadNoiseDarkCurrentAdc, SensorPrediction,
    ::testing::Values(
        SensorCase{"Numerical", ShutterMode::kNumerical, NoiseModel::kPoisson, true},
        SensorCase{"Analog", ShutterMode::kAnalog, NoiseModel::kPoisson, true},
        // a linear sensor: the frames' read noise drawn as one normal per pixel
        SensorCase{"NumericalLinear", ShutterMode::kNumerical, NoiseModel::kPoisson, false},
        SensorCase{"NumericalAggregated", ShutterMode::kNumerical, NoiseModel::kAggregated, false}),
    [](const ::testing::TestParamInfo<SensorCase>& info) { return std::string(info.param.name); });

TEST(SensorPrediction, ConstantLandscapeAtRestAddsTheReadoutVariance) {
  // Snapshot at v = 0: the restoration is the observation, one readout of
  // one slot per pixel, at a level on the normal branch:
  //   exact:      100 / lambda2 + (1/12 + sigma_r^2 + d dt + G^2/12) / lambda2^2
  //   stationary: 100 / lambda2 + (sigma_r^2 + d dt + G^2/12) / lambda2^2
  const Image flat(300, 4, 1, 100.0);
  SimulationOptions options;
  options.velocity_px_per_slot = 0.0;
  options.snr = 30.0;
  options.dt = 2.0;
  options.rmse_margin_columns = 0;
  options.sensor = test_sensor();
  options.sensor.adc_bits = 20;  // the ADC's top far above the charge
  const SimulationReport r = Simulate(options, flat, *builtin_code("snapshot"));
  const double lambda2 = 9.0;
  const double readout = 64.0 + 2.0 * 2.0 + 4.0 / 12.0;
  // level 100 seen for dt = 2 slots; the snapshot's K(0) = dt divides it.
  const double photon = 100.0 * 2.0 / lambda2 / 4.0;
  EXPECT_NEAR(r.prediction.noise * r.prediction.noise,
              photon + (1.0 / 12.0 + readout) / (lambda2 * lambda2) / 4.0, 1e-12);
  EXPECT_NEAR(r.prediction.sigma * r.prediction.sigma, photon + readout / (lambda2 * lambda2) / 4.0,
              1e-12);
  EXPECT_NEAR(r.prediction.snr_level100, 100.0 / std::sqrt(photon + readout / 81.0 / 4.0), 1e-9);
  EXPECT_TRUE(r.prediction.exact);
}

TEST(SensorPrediction, Level100SnrFallsFasterWithReadNoiseInTheNumericalMode) {
  // Numerical: L readouts weighted alpha_k^2; analog: one readout.
  const std::vector<double> gains = kAnalogGains;
  const double m = 1.7;
  double previous_numerical = INFINITY;
  double previous_analog = INFINITY;
  for (const double read_noise : {0.0, 5.0, 10.0, 20.0}) {
    SensorModel s;
    s.read_noise_electrons = read_noise;
    const double numerical = snr_level100(gains, 1.0, ShutterMode::kNumerical, m, 10.0, s);
    const double analog = snr_level100(gains, 1.0, ShutterMode::kAnalog, m, 10.0, s);
    EXPECT_LT(numerical, previous_numerical);
    EXPECT_LT(analog, previous_analog);
    if (read_noise == 0.0) {
      EXPECT_EQ(numerical, snr_level100(noise_gain(gains, 1.0, ShutterMode::kNumerical), m, 10.0));
      EXPECT_EQ(analog, snr_level100(noise_gain(gains, 1.0, ShutterMode::kAnalog), m, 10.0));
    } else {
      EXPECT_LT(numerical / previous_numerical, analog / previous_analog);
    }
    previous_numerical = numerical;
    previous_analog = analog;
  }
}

// --- clipping ----------------------------------------------------------------

TEST(SensorClipping, SaturationIsWarnedAndThePredictionMarkedApproximate) {
  SimulationOptions options;
  options.sensor.full_well_electrons = 15000.0;  // level 150 at snr 100
  const SimulationReport r =
      Simulate(options, test::make_test_image(480, 8, 1), *builtin_code("raskar"));
  EXPECT_FALSE(r.prediction.exact);
  const std::vector<std::string> warnings = warnings_but_ssim(r);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("readouts saturate"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("approximate"), std::string::npos) << warnings[0];
  // A full well out of reach clips nothing: exact, no warning.
  options.sensor.full_well_electrons = 1e6;
  const SimulationReport free =
      Simulate(options, test::make_test_image(480, 8, 1), *builtin_code("raskar"));
  EXPECT_TRUE(free.prediction.exact);
  EXPECT_TRUE(warnings_but_ssim(free).empty());
}

TEST(SensorClipping, SaturationIsWarnedWithoutNoiseToo) {
  SimulationOptions options;
  options.noise = NoiseModel::kNone;
  options.sensor.full_well_electrons = 15000.0;
  const SimulationReport r =
      Simulate(options, test::make_test_image(480, 8, 1), *builtin_code("raskar"));
  EXPECT_FALSE(r.prediction.exact);
  ASSERT_EQ(warnings_but_ssim(r).size(), 1u);
  // the expectation is clipped: no observed value above the well's level
  // (150 gray levels a slot, times the 26 open slots, over K(0) = 26)
  for (const double v : r.observed.data) EXPECT_LE(v, 150.0 + 1e-9);
}

TEST(SensorClipping, AdcNearZeroIsWarned) {
  // A dark scene with read noise: readouts near 0, which the ADC clips.
  SimulationOptions options;
  options.sensor.read_noise_electrons = 10.0;
  options.sensor.adc_bits = 12;
  Image dark(480, 4, 1, 0.0);
  const SimulationReport r = Simulate(options, dark, *builtin_code("raskar"));
  EXPECT_FALSE(r.prediction.exact);
  const std::vector<std::string> warnings = warnings_but_ssim(r);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("within 3 standard deviations of 0"), std::string::npos);
}

// --- noise none, determinism --------------------------------------------------

TEST(SensorNoiseFree, LinearSensorObservesTheExpectation) {
  // No noise: read noise and dark current (after its subtraction) have mean
  // 0, so the run is the photon-only noise-free run, byte for byte.
  const Image input = test::make_test_image(480, 6, 1, 3);
  SimulationOptions options;
  options.noise = NoiseModel::kNone;
  const SimulationReport plain = Simulate(options, input, *builtin_code("mip"));
  options.sensor.read_noise_electrons = 7.0;
  options.sensor.dark_current_electrons_per_slot = 3.0;
  const SimulationReport sensor = Simulate(options, input, *builtin_code("mip"));
  EXPECT_EQ(plain.observed.data, sensor.observed.data);
  EXPECT_EQ(plain.restored.data, sensor.restored.data);
}

TEST(SensorDeterminism, ThreadCountDoesNotChangeTheResults) {
  const Image input = test::make_test_image(480, 20, 3, 9);
  for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
    SimulationOptions options;
    options.mode = mode;
    options.velocity_px_per_slot = 0.6;
    options.trials = 2;
    options.sensor = test_sensor();
    options.sensor.full_well_electrons = 20000.0;
    options.threads = 1;
    const SimulationReport one = Simulate(options, input, *builtin_code("raskar"));
    options.threads = 3;
    const SimulationReport three = Simulate(options, input, *builtin_code("raskar"));
    EXPECT_EQ(one.observed.data, three.observed.data);
    EXPECT_EQ(one.restored.data, three.restored.data);
    EXPECT_EQ(one.prediction.rmse, three.prediction.rmse);
    EXPECT_EQ(one.warnings, three.warnings);
    // and the read noise changes the noise: not the photon-only run
    options.sensor = SensorModel();
    const SimulationReport photon = Simulate(options, input, *builtin_code("raskar"));
    EXPECT_NE(photon.restored.data, one.restored.data);
  }
}

}  // namespace
}  // namespace fss
