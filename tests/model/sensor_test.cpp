// Tests of fss/model/sensor.h and of the samplers' readouts (noise.h,
// docs/method.md §10): the options' rules, the readout's arithmetic, and the
// statistics of each term (read noise, dark current, full well, ADC) on
// constant rows, within 5 standard errors with fixed seeds (deterministic,
// failing only on a real bias).
#include "fss/model/sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fss/pipeline/prediction.h"
#include "model/noise.h"

namespace fss {
namespace {

// --- SensorModel ----------------------------------------------------------

TEST(SensorModel, DefaultIsOffLinearAndValid) {
  const SensorModel sensor;
  EXPECT_FALSE(sensor.enabled());
  EXPECT_TRUE(sensor.linear());
  std::string error = "untouched";
  EXPECT_TRUE(sensor.IsValid(&error));
  EXPECT_EQ(error, "untouched");
}

TEST(SensorModel, EachPartEnablesIt) {
  SensorModel a;
  a.read_noise_electrons = 1.0;
  SensorModel b;
  b.dark_current_electrons_per_slot = 0.5;
  SensorModel c;
  c.full_well_electrons = 1000.0;
  SensorModel d;
  d.adc_bits = 12;
  for (const SensorModel& s : {a, b, c, d}) EXPECT_TRUE(s.enabled());
  EXPECT_TRUE(a.linear());
  EXPECT_TRUE(b.linear());
  EXPECT_FALSE(c.linear());
  EXPECT_FALSE(d.linear());
  SensorModel gain_only;  // the gain alone is not an ADC
  gain_only.adc_gain_electrons_per_count = 3.0;
  EXPECT_FALSE(gain_only.enabled());
}

struct InvalidSensor {
  SensorModel sensor;
  std::string message;
};

SensorModel with(void (*set)(SensorModel&)) {
  SensorModel s;
  set(s);
  return s;
}

TEST(SensorModel, InvalidFieldsAreNamedWithValueAndRule) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  static double bad_nan = nan;
  const std::vector<InvalidSensor> cases = {
      {with([](SensorModel& s) { s.read_noise_electrons = -1.0; }),
       "read_noise_electrons = -1: must be finite and >= 0"},
      {with([](SensorModel& s) { s.read_noise_electrons = bad_nan; }),
       "read_noise_electrons = nan: must be finite and >= 0"},
      {with([](SensorModel& s) { s.dark_current_electrons_per_slot = -0.5; }),
       "dark_current_electrons_per_slot = -0.5: must be finite and >= 0"},
      {with([](SensorModel& s) { s.full_well_electrons = 0.0; }),
       "full_well_electrons = 0: must be finite and > 0"},
      {with([](SensorModel& s) { s.adc_bits = 33; }),
       "adc_bits = 33: must lie in [1, 32] (or 0 for no ADC)"},
      {with([](SensorModel& s) { s.adc_bits = -1; }),
       "adc_bits = -1: must lie in [1, 32] (or 0 for no ADC)"},
      {with([](SensorModel& s) { s.adc_gain_electrons_per_count = 0.0; }),
       "adc_gain_electrons_per_count = 0: must be finite and > 0"},
  };
  for (const InvalidSensor& c : cases) {
    std::string error;
    EXPECT_FALSE(c.sensor.IsValid(&error)) << c.message;
    EXPECT_EQ(error, c.message);
  }
}

TEST(SensorModel, ReadoutExposureAndVariance) {
  EXPECT_EQ(readout_exposure_slots(52, 0.5, ShutterMode::kNumerical), 0.5);
  EXPECT_EQ(readout_exposure_slots(52, 0.5, ShutterMode::kAnalog), 26.0);
  SensorModel s;
  s.read_noise_electrons = 3.0;
  s.dark_current_electrons_per_slot = 2.0;
  EXPECT_DOUBLE_EQ(readout_variance_electrons2(s, 4.0), 9.0 + 8.0);
  s.adc_bits = 10;
  s.adc_gain_electrons_per_count = 6.0;
  EXPECT_DOUBLE_EQ(readout_variance_electrons2(s, 4.0), 9.0 + 8.0 + 36.0 / 12.0);
  EXPECT_EQ(readout_variance_electrons2(SensorModel(), 4.0), 0.0);
}

TEST(SensorModel, Level100VarianceOfADefaultSensorIsThePhotonNoise) {
  const std::vector<double> gains = {1.0, 0.0, 0.5, 1.0, 0.25};
  for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
    // 100 Q (100 / snr^2)
    const double expected = 100.0 * noise_gain(gains, 0.7, mode) * 100.0 / (30.0 * 30.0);
    EXPECT_NEAR(level100_observation_variance(gains, 0.7, mode, 30.0, SensorModel()), expected,
                1e-12 * expected);
  }
}

TEST(SensorModel, Level100VarianceCountsTheReadouts) {
  // numerical: one readout per frame weighted alpha_k^2; analog: one readout.
  const std::vector<double> gains = {1.0, 0.0, 0.5, 1.0};
  SensorModel s;
  s.read_noise_electrons = 4.0;
  s.dark_current_electrons_per_slot = 1.0;
  const double snr = 20.0;
  const double lambda2 = snr * snr / 100.0;
  const double dt = 2.0;
  const double photon_numerical =
      level100_observation_variance(gains, dt, ShutterMode::kNumerical, snr, SensorModel());
  const double photon_analog =
      level100_observation_variance(gains, dt, ShutterMode::kAnalog, snr, SensorModel());
  const double sum_sq = 1.0 + 0.25 + 1.0;
  EXPECT_NEAR(level100_observation_variance(gains, dt, ShutterMode::kNumerical, snr, s),
              photon_numerical + sum_sq * (16.0 + 1.0 * dt) / (lambda2 * lambda2), 1e-12);
  EXPECT_NEAR(level100_observation_variance(gains, dt, ShutterMode::kAnalog, snr, s),
              photon_analog + (16.0 + 1.0 * dt * 4.0) / (lambda2 * lambda2), 1e-12);
}

// --- SensorReadout::read --------------------------------------------------

TEST(SensorReadout, DefaultReadsTheChargeUnchanged) {
  const SensorReadout r = sensor_readout(SensorModel(), 1.0);
  EXPECT_FALSE(r.adc());
  EXPECT_EQ(r.clip_electrons(), std::numeric_limits<double>::infinity());
  for (const double q : {0.0, 1.0, 37.0, 1e6}) EXPECT_EQ(r.read(q, 0.7), q);
}

TEST(SensorReadout, ClipsAddsReadNoiseQuantizesAndSubtractsTheDarkMean) {
  SensorModel s;
  s.read_noise_electrons = 2.0;
  s.dark_current_electrons_per_slot = 1.5;
  s.full_well_electrons = 100.0;
  s.adc_bits = 4;  // counts 0..15
  s.adc_gain_electrons_per_count = 10.0;
  const SensorReadout r = sensor_readout(s, 2.0);
  EXPECT_EQ(r.dark_electrons, 3.0);
  EXPECT_EQ(r.adc_max_counts, 15.0);
  EXPECT_EQ(r.clip_electrons(), 100.0);  // min(F, 15 G = 150)
  // 40 + 2 * 1.3 = 42.6 -> 4 counts -> 40 e-, minus 3
  EXPECT_EQ(r.read(40.0, 1.3), 37.0);
  // 44 + 2 * 0.5 = 45 -> 4.5 counts, rounded half up -> 50, minus 3
  EXPECT_EQ(r.read(44.0, 0.5), 47.0);
  // the full well: min(500, 100) + 2 * 0 = 100 -> 10 counts
  EXPECT_EQ(r.read(500.0, 0.0), 97.0);
  // a negative readout gives 0 counts
  EXPECT_EQ(r.read(1.0, -3.0), -3.0);
  // the ADC's top: 15 counts
  s.full_well_electrons.reset();
  const SensorReadout top = sensor_readout(s, 2.0);
  EXPECT_EQ(top.clip_electrons(), 150.0);
  EXPECT_EQ(top.read(1e6, 0.0), 150.0 - 3.0);
}

// A mean charge exactly at the clip saturates (its readouts are cut there);
// the next double below does not. Both the full well and the ADC's top.
TEST(SensorReadout, SaturatesFromTheClipOn) {
  SensorModel s;
  s.full_well_electrons = 10000.0;
  const SensorReadout well = sensor_readout(s, 1.0);
  EXPECT_TRUE(well.saturates(10000.0));
  EXPECT_TRUE(well.saturates(std::nextafter(10000.0, 1e9)));
  EXPECT_FALSE(well.saturates(std::nextafter(10000.0, 0.0)));
  s.full_well_electrons.reset();
  s.adc_bits = 4;  // top: 15 counts of 10 e-
  s.adc_gain_electrons_per_count = 10.0;
  const SensorReadout adc = sensor_readout(s, 1.0);
  EXPECT_TRUE(adc.saturates(150.0));
  EXPECT_FALSE(adc.saturates(std::nextafter(150.0, 0.0)));
  EXPECT_FALSE(SensorReadout().saturates(1e308));  // no sensor: nothing clips
}

// --- the samplers' readouts on constant rows ------------------------------

struct Moments {
  double mean = 0.0;
  double variance = 0.0;
  int n = 0;
  double mean_se() const { return std::sqrt(variance / n); }
  // Standard error of the sample variance, close to normal samples'.
  double variance_se() const { return variance * std::sqrt(2.0 / (n - 1)); }
};

Moments moments(const std::vector<double>& xs) {
  double mean = 0.0;
  double m2 = 0.0;
  int i = 0;
  for (const double x : xs) {
    ++i;
    const double delta = x - mean;
    mean += delta / i;
    m2 += delta * (x - mean);
  }
  return {mean, m2 / (i - 1), i};
}

constexpr int kWidth = 4096;
constexpr int kRows = 16;

// `rows` rows of a constant exposure e through the per-frame sampler with
// `readout`, gain `gain` (rows are independent streams).
std::vector<double> sample_rows(double snr, double e, const SensorReadout& readout,
                                double gain = 1.0, std::uint64_t seed = 3, int rows = kRows) {
  PoissonRowSampler sampler(snr);
  const std::vector<double> exposure(kWidth, e);
  std::vector<double> all;
  for (int y = 0; y < rows; ++y) {
    std::vector<double> out(kWidth, 0.0);
    sampler.accumulate_readout(exposure, {seed, 0, 2, static_cast<std::uint64_t>(y)}, gain, readout,
                               out);
    all.insert(all.end(), out.begin(), out.end());
  }
  return all;
}

void expect_moments(const std::vector<double>& xs, double mean, double variance) {
  const Moments m = moments(xs);
  EXPECT_NEAR(m.mean, mean, 5.0 * m.mean_se()) << "variance " << m.variance;
  EXPECT_NEAR(m.variance, variance, 5.0 * m.variance_se()) << "mean " << m.mean;
}

TEST(SensorSampler, ReadNoiseAddsItsVarianceAndNoBias) {
  // lambda2 = 1 (snr 10): e electrons. Knuth's branch (e = 20) and the
  // normal one (e = 300, + 1/12 for the rounding).
  SensorModel s;
  s.read_noise_electrons = 6.0;
  const SensorReadout r = sensor_readout(s, 1.0);
  expect_moments(sample_rows(10.0, 20.0, r), 20.0, 20.0 + 36.0);
  expect_moments(sample_rows(10.0, 300.0, r), 300.0, 300.0 + 1.0 / 12.0 + 36.0);
  // in gray levels at lambda2 = 4 (snr 20): (4 e + 36) / 16
  expect_moments(sample_rows(20.0, 30.0, r), 30.0, (120.0 + 1.0 / 12.0 + 36.0) / 16.0);
}

TEST(SensorSampler, DarkCurrentAddsItsShotNoiseAndItsMeanIsSubtracted) {
  SensorModel s;
  s.dark_current_electrons_per_slot = 4.0;
  const SensorReadout r = sensor_readout(s, 2.5);  // 10 dark electrons a readout
  // Knuth's branch: Poisson(15 + 10) - 10
  expect_moments(sample_rows(10.0, 15.0, r), 15.0, 25.0);
  // across the branch limit: lambda 45 + 10 = 55 is drawn on the normal branch
  expect_moments(sample_rows(10.0, 45.0, r), 45.0, 55.0 + 1.0 / 12.0);
  // a dark scene: only dark charge, mean 0 after the correction
  expect_moments(sample_rows(10.0, 0.0, r), 0.0, 10.0);
}

TEST(SensorSampler, PhotonDrawsAreThoseOfThePhotonOnlySampler) {
  // A sensor that changes nothing (no read noise, no dark current, a full
  // well out of reach) draws the very same charges from the same lanes.
  SensorReadout r;
  r.full_well_electrons = 1e300;
  PoissonRowSampler a(10.0);
  PoissonRowSampler b(10.0);
  std::vector<double> e(kWidth);
  for (int x = 0; x < kWidth; ++x) e[x] = 0.05 * x;  // both branches
  std::vector<double> plain(kWidth, 0.0);
  std::vector<double> sensor(kWidth, 0.0);
  a.accumulate(e, {9, 1, 4, 7}, 0.75, plain);
  b.accumulate_readout(e, {9, 1, 4, 7}, 0.75, r, sensor);
  EXPECT_EQ(plain, sensor);
}

TEST(SensorSampler, FullWellClipsEachChargeAtTheWell) {
  // The same variates with and without the well: pixel by pixel, the
  // clipped readout is min(charge, F) (no read noise, lambda2 = 1).
  SensorModel s;
  s.full_well_electrons = 205.0;
  const SensorReadout well = sensor_readout(s, 1.0);
  const std::vector<double> free = sample_rows(10.0, 200.0, SensorReadout());
  const std::vector<double> clipped = sample_rows(10.0, 200.0, well);
  int at_well = 0;
  for (std::size_t i = 0; i < free.size(); ++i) {
    ASSERT_EQ(clipped[i], std::min(free[i], 205.0)) << i;
    at_well += clipped[i] == 205.0 ? 1 : 0;
  }
  // P(round(200 + sqrt(200) N) >= 205) = P(N >= 4.5 / sqrt(200)) = 0.375
  const double p = 0.5 * std::erfc(4.5 / std::sqrt(200.0) / std::sqrt(2.0));
  const double n = static_cast<double>(free.size());
  EXPECT_NEAR(at_well / n, p, 5.0 * std::sqrt(p * (1.0 - p) / n));
}

TEST(SensorSampler, AdcRoundsToCountsWithinItsRange) {
  // Same variates with and without the ADC: pixel by pixel the ADC's
  // readout is min(round+(q / G), 2^b - 1) G of the analog readout q.
  SensorModel s;
  s.read_noise_electrons = 8.0;
  const SensorReadout analog = sensor_readout(s, 1.0);
  s.adc_bits = 7;  // 0..127 counts
  s.adc_gain_electrons_per_count = 3.0;
  const SensorReadout adc = sensor_readout(s, 1.0);
  // e = 10: many readouts below 0 (clipped to 0); e = 370: many above 381
  for (const double e : {10.0, 370.0}) {
    const std::vector<double> q = sample_rows(10.0, e, analog);
    const std::vector<double> counted = sample_rows(10.0, e, adc);
    int low = 0;
    int high = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const double counts = std::min(round_nonnegative(q[i] / 3.0), 127.0);
      ASSERT_EQ(counted[i], counts * 3.0) << i;
      low += counted[i] == 0.0 ? 1 : 0;
      high += counted[i] == 381.0 ? 1 : 0;
    }
    EXPECT_GT(e < 100.0 ? low : high, 1000);
  }
}

TEST(SensorSampler, AdcQuantizationAddsGainSquaredOverTwelve) {
  // Away from the range's ends, with a noise much wider than a count, the
  // rounding adds G^2 / 12 of variance and no bias.
  SensorModel s;
  s.read_noise_electrons = 10.0;
  s.dark_current_electrons_per_slot = 3.0;
  s.adc_bits = 16;
  s.adc_gain_electrons_per_count = 4.0;
  const SensorReadout r = sensor_readout(s, 1.0);
  EXPECT_DOUBLE_EQ(readout_variance_electrons2(s, 1.0), 100.0 + 3.0 + 16.0 / 12.0);
  // lambda2 = 1: Var = 250 + 1/12 (normal branch) + 100 + 3 + 16/12
  expect_moments(sample_rows(10.0, 250.0, r, 1.0, 5, 32), 250.0,
                 250.0 + 1.0 / 12.0 + readout_variance_electrons2(s, 1.0));
}

TEST(SensorSampler, GainScalesTheReadout) {
  SensorModel s;
  s.read_noise_electrons = 5.0;
  s.dark_current_electrons_per_slot = 2.0;
  const SensorReadout r = sensor_readout(s, 1.0);
  // alpha = -0.5 (numerical gains may be negative), lambda2 = 1
  expect_moments(sample_rows(10.0, 100.0, r, -0.5), -50.0, 0.25 * (102.0 + 1.0 / 12.0 + 25.0));
}

TEST(SensorSampler, ReadNoiseIsIndependentOfThePhotonNoise) {
  // Read noise has its own lane: the readout minus the charge of the
  // photon-only sampler (same seed) is N(0, sigma_r^2), uncorrelated with it.
  SensorModel s;
  s.read_noise_electrons = 3.0;
  const std::vector<double> photon = sample_rows(10.0, 80.0, SensorReadout());
  const std::vector<double> read = sample_rows(10.0, 80.0, sensor_readout(s, 1.0));
  std::vector<double> difference(photon.size());
  double covariance = 0.0;
  for (std::size_t i = 0; i < photon.size(); ++i) {
    difference[i] = read[i] - photon[i];
    covariance += (photon[i] - 80.0) * difference[i];
  }
  expect_moments(difference, 0.0, 9.0);
  const double n = static_cast<double>(photon.size());
  // correlation within 5 / sqrt(n)
  EXPECT_LT(std::abs(covariance / n / std::sqrt(80.0 * 9.0)), 5.0 / std::sqrt(n));
}

TEST(SensorSampler, AggregatedReadoutHasTheSameMeanAndVariance) {
  // Aggregated sampler with dark current and read noise: per pixel mean
  // sum alpha_k e_k and variance sum alpha_k^2 (lambda_k + d + [1/12] + sigma^2).
  SensorModel s;
  s.read_noise_electrons = 4.0;
  s.dark_current_electrons_per_slot = 6.0;
  const SensorReadout r = sensor_readout(s, 1.0);
  const std::vector<double> gains = {1.0, -0.5, 0.8};
  const std::vector<double> levels = {30.0, 200.0, 70.0};  // Knuth (36 < 50) and normal frames
  AggregatedRowSampler sampler(10.0);
  std::vector<double> all;
  for (int y = 0; y < kRows; ++y) {
    std::vector<double> out(kWidth, 0.0);
    for (std::size_t k = 0; k < gains.size(); ++k) {
      const std::vector<double> e(kWidth, levels[k]);
      sampler.add_frame(e, {21, 0, k, static_cast<std::uint64_t>(y)}, gains[k], out, &r);
    }
    sampler.finish({21, 0, 0, static_cast<std::uint64_t>(y)}, out);
    all.insert(all.end(), out.begin(), out.end());
  }
  double mean = 0.0;
  double variance = 0.0;
  for (std::size_t k = 0; k < gains.size(); ++k) {
    const double lambda = levels[k] + 6.0;
    mean += gains[k] * levels[k];
    variance += gains[k] * gains[k] * (lambda + (lambda >= 50.0 ? 1.0 / 12.0 : 0.0) + 16.0);
  }
  expect_moments(all, mean, variance);
}

}  // namespace
}  // namespace fss
