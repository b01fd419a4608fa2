// Statistical validation of the aggregated photon noise (docs/method.md §6c)
// against the per-frame sampler (§3) through the whole pipeline: per-pixel
// mean and variance maps of the observation, the means of RMSE and RMSE_CI
// over many trials for every code of the paper, and the exact prediction,
// which has no rounding term for the grouped frames (drawn as one exact
// Poisson). Plus the option's wiring: names, refusal with the analog mode,
// reproducibility, replay of recorded rows, the per-frame sampler unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fss/campaign/spec.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"
#include "model/noise.h"
#include "pipeline/observe.h"
#include "support/reference_paths.h"
#include "support/test_util.h"

namespace fss {
namespace {

// ---------------------------------------------------------------------------
// The option

TEST(AggregatedNoise, NameRoundTrips) {
  for (const NoiseModel noise :
       {NoiseModel::kPoisson, NoiseModel::kNone, NoiseModel::kAggregated}) {
    EXPECT_EQ(noise_model_from_string(to_string(noise)), noise);
  }
  EXPECT_EQ(to_string(NoiseModel::kAggregated), "aggregated");
  EXPECT_FALSE(noise_model_from_string("Aggregated").has_value());
}

TEST(AggregatedNoise, RefusedInAnalogMode) {
  SimulationOptions options;
  options.noise = NoiseModel::kAggregated;
  EXPECT_TRUE(options.IsValid(nullptr));
  options.mode = ShutterMode::kAnalog;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("noise = aggregated: must be poisson or none in analog mode"),
            std::string::npos)
      << error;
  const Image input = test::make_test_image(480, 2, 1);
  EXPECT_TRUE(test::throws_error([&] { Simulate(options, input, builtin_code("raskar").value()); },
                                 ErrorKind::kUsage, {"noise = aggregated", "analog"}));
}

TEST(AggregatedNoise, CommandLineRefusesItInAnalogMode) {
  const test::CommandResult r =
      test::run_fssim("-i " + test::quote(test::source_path("data/camera.png")) +
                      " --mode analog --noise aggregated --outdir /nonexistent/never-written");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--noise: value aggregated must be poisson or none in analog mode"),
            std::string::npos)
      << r.err;
}

TEST(AggregatedNoise, SameBytesForAnyThreadCountAndNonIntegerMotion) {
  const Image input = test::make_test_image(500, 6, 3, 7);
  SimulationOptions options;
  options.noise = NoiseModel::kAggregated;
  options.velocity_px_per_slot = -0.73;
  options.dt = 1.3;
  options.snr = 20.0;  // both branches
  options.trials = 3;
  options.seed = 99;
  options.threads = 1;
  const ShutterCode code = builtin_code("mip").value();
  const SimulationReport one = Simulate(options, input, code);
  options.threads = 3;
  const SimulationReport three = Simulate(options, input, code);
  EXPECT_TRUE(one.observed.data == three.observed.data);
  EXPECT_TRUE(one.restored.data == three.restored.data);
  EXPECT_EQ(one.trials.rmse_mean, three.trials.rmse_mean);
  EXPECT_EQ(one.trials.rmse_ci_mean, three.trials.rmse_ci_mean);
  // And it is noise: another seed, another observation; the per-frame
  // sampler draws other variates.
  options.seed = 100;
  EXPECT_FALSE(Simulate(options, input, code).observed.data == one.observed.data);
  options.seed = 99;
  options.noise = NoiseModel::kPoisson;
  EXPECT_FALSE(Simulate(options, input, code).observed.data == one.observed.data);
}

// Trials share the work: the first trial records each row's plan, the
// others replay it. Same bytes as drawing every row from its frames.
// mip: single frames only; raskar: one group; two_groups: two groups;
// mixed: one group and single frames; sinc: 23 groups and one single frame.
// Filtered frames (velocity 0.6) and shifts (velocity 1).
struct ReplayCase {
  const char* code;
  double velocity;
};

std::vector<double> replay_gains(const std::string& name) {
  if (name == "two_groups") return {1.0, 0.5, 1.0, 0.0, 0.5, 1.0, 0.5, 0.5};
  if (name == "mixed") return {1.0, 0.7, 1.0, 0.2, 1.0, 0.9, 0.0, 0.4};
  return test::paper_gains(name);
}

class ReplayedRow : public ::testing::TestWithParam<ReplayCase> {};

TEST_P(ReplayedRow, IsTheDrawnRow) {
  const ReplayCase c = GetParam();
  const std::string name = c.code;
  Image input = test::make_test_image(200, 3, 1, 5);
  for (int x = 0; x < 2; ++x) input.at(0, 1, x) = 0.0;  // Knuth frames on row 1
  for (const double snr : {3.0, 12.0, 100.0}) {
    ObservationParams params;
    params.velocity = c.velocity;
    params.snr = snr;
    params.aggregate_noise = true;
    const std::vector<double> gains = replay_gains(name);
    const RowObserver observer(input.width, gains, ShutterMode::kNumerical, params);
    ASSERT_TRUE(observer.aggregates_noise());
    RowObserver::Scratch scratch(observer);
    std::vector<double> drawn(200), replayed(200);
    int recorded_rows = 0;
    for (int y = 0; y < input.height; ++y) {
      AggregatedRowPlan plan;
      observer.load_row(input.row(0, y), scratch);
      observer.record_plan(&plan, scratch);
      observer.observe(true, 40, 0, y, scratch, drawn);
      if (!plan.recorded) continue;
      ++recorded_rows;
      for (const std::uint64_t seed : {40, 41, 12345}) {
        observer.load_row(input.row(0, y), scratch);
        observer.observe(true, seed, 0, y, scratch, drawn);
        observer.replay(plan, seed, 0, y, scratch, replayed);
        EXPECT_TRUE(drawn == replayed) << "snr " << snr << " row " << y << " seed " << seed;
      }
    }
    // mip at snr 3: every frame on Knuth's branch, more pixel frames than
    // the width, nothing recorded; at snr 100: only about 2 x 52 pixel
    // frames of row 1 on Knuth's branch, every row recorded. The grouped
    // frames have no Knuth branch: raskar's and two_groups' rows are all
    // recorded, and so are sinc's at snr 100 (its 23 groups' Lambda within a
    // plan's bound, which grows with the code's groups).
    if (name == "mip" && snr == 3.0) EXPECT_EQ(recorded_rows, 0);
    if (name == "mip" && snr == 100.0) EXPECT_EQ(recorded_rows, input.height);
    if (name == "raskar" || name == "two_groups" || (name == "mixed" && snr == 100.0)) {
      EXPECT_EQ(recorded_rows, input.height) << "snr " << snr;
    }
    if (name == "sinc" && snr == 100.0) EXPECT_EQ(recorded_rows, input.height) << "snr " << snr;
  }
}

INSTANTIATE_TEST_SUITE_P(Codes, ReplayedRow,
                         ::testing::Values(ReplayCase{"mip", 0.6}, ReplayCase{"sinc", 0.6},
                                           ReplayCase{"raskar", 0.6}, ReplayCase{"raskar", 1.0},
                                           ReplayCase{"two_groups", 0.6},
                                           ReplayCase{"two_groups", 1.0}, ReplayCase{"mixed", 0.6},
                                           ReplayCase{"mixed", 1.0}),
                         [](const auto& info) {
                           return std::string(info.param.code) +
                                  (info.param.velocity == 1.0 ? "_shifts" : "_filtered");
                         });

// The frames of equal gains: groups numbered in the order of their first
// frames, zero and unique gains single.
TEST(AggregatedNoise, GainGroupsAreTheSharedNonzeroGains) {
  const std::vector<double> gains = {0.5, 0.0, 1.0, 0.5, 0.25, 0.0, 1.0, 1.0, -0.5, 0.5};
  const std::vector<int> expected = {0, kSingleFrame, 1, 0, kSingleFrame, kSingleFrame, 1,
                                     1, kSingleFrame, 0};
  EXPECT_EQ(gain_groups(gains), expected);
  EXPECT_TRUE(gain_groups({}).empty());
  // The paper's codes: raskar's 26 open frames one group, mip's gains all
  // different, sinc's symmetric pairs (and its unique centre).
  const auto count = [](const std::vector<int>& groups, bool grouped) {
    return std::count_if(groups.begin(), groups.end(),
                         [&](int g) { return (g != kSingleFrame) == grouped; });
  };
  const std::vector<int> raskar = gain_groups(test::paper_gains("raskar"));
  EXPECT_EQ(count(raskar, true), 26);
  EXPECT_EQ(*std::max_element(raskar.begin(), raskar.end()), 0);
  EXPECT_EQ(count(gain_groups(test::paper_gains("mip")), true), 0);
  const std::vector<int> sinc = gain_groups(test::paper_gains("sinc"));
  EXPECT_EQ(count(sinc, false), 1);
  EXPECT_EQ(*std::max_element(sinc.begin(), sinc.end()), 22);
}

// Var(o) of the noise-free pass follows the sampler: with aggregated noise a
// grouped frame has no rounding term 1 / (12 lambda2^2), a single frame
// keeps it; without groups (mip) the bytes are the per-frame sampler's.
TEST(AggregatedNoise, ExactVarianceDropsTheGroupedFramesRoundingTerm) {
  const Image input = test::make_test_image(160, 2, 1, 9);
  for (const char* name : {"raskar", "sinc", "mip"}) {
    for (const double velocity : {1.0, 0.6}) {
      const std::vector<double> gains = test::paper_gains(name);
      const std::vector<int> groups = gain_groups(gains);
      ObservationParams params;
      params.velocity = velocity;
      params.snr = 30.0;  // lambda2 = 9: both branches
      const double lambda2 = 9.0;
      const RowObserver per_frame(input.width, gains, ShutterMode::kNumerical, params);
      params.aggregate_noise = true;
      const RowObserver aggregated(input.width, gains, ShutterMode::kNumerical, params);
      RowObserver::Scratch s1(per_frame), s2(aggregated), s3(per_frame);
      std::vector<double> e1(160), v1(160), e2(160), v2(160), frame(160), unused(160);
      for (int y = 0; y < input.height; ++y) {
        per_frame.load_row(input.row(0, y), s1);
        per_frame.observe(false, 0, 0, y, s1, e1, v1);
        aggregated.load_row(input.row(0, y), s2);
        aggregated.observe(false, 0, 0, y, s2, e2, v2);
        EXPECT_TRUE(e1 == e2);
        // The grouped frames' rounding terms: 1 / (12 lambda2^2) for each
        // grouped frame whose lambda = max(e_k, 0) lambda2 is >= 50.
        std::vector<double> rounding(160, 0.0);
        for (std::size_t k = 0; k < gains.size(); ++k) {
          if (groups[k] == kSingleFrame) continue;
          std::vector<double> unit(gains.size(), 0.0);
          unit[k] = 1.0;
          const RowObserver slot(input.width, unit, ShutterMode::kNumerical, params);
          RowObserver::Scratch scratch(slot);
          slot.load_row(input.row(0, y), scratch);
          slot.observe(false, 0, 0, y, scratch, frame);
          for (int x = 0; x < 160; ++x) {
            if (frame[x] * lambda2 >= kKnuthLimit) {
              rounding[x] += gains[k] * gains[k] / (12.0 * lambda2 * lambda2);
            }
          }
        }
        for (int x = 0; x < 160; ++x) {
          EXPECT_NEAR(v1[x] - v2[x], rounding[x], 1e-12 * v1[x]) << name << " pixel " << x;
        }
        if (std::string(name) == "mip") EXPECT_TRUE(v1 == v2) << "row " << y;
        if (std::string(name) == "raskar") {
          EXPECT_GT(*std::max_element(rounding.begin(), rounding.end()), 0.0);
        }
      }
    }
  }
}

// The default sampler draws each frame on its own: the poisson observation
// of a code with repeated gains is, byte for byte, the sum over its frames
// of PoissonRowSampler's draws of each frame's exposure, as before groups.
TEST(AggregatedNoise, PerFrameSamplerIgnoresTheGroups) {
  const Image input = test::make_test_image(150, 2, 1, 4);
  for (const char* name : {"raskar", "sinc"}) {
    for (const double velocity : {1.0, 0.6}) {
      const std::vector<double> gains = test::paper_gains(name);
      ObservationParams params;
      params.velocity = velocity;
      params.snr = 20.0;
      const RowObserver observer(input.width, gains, ShutterMode::kNumerical, params);
      RowObserver::Scratch scratch(observer);
      PoissonRowSampler sampler(params.snr);
      std::vector<double> noisy(150), frame(150);
      for (int y = 0; y < input.height; ++y) {
        observer.load_row(input.row(0, y), scratch);
        observer.observe(true, 77, 0, y, scratch, noisy);
        std::vector<double> sum(150, 0.0);
        for (std::size_t k = 0; k < gains.size(); ++k) {
          if (gains[k] == 0.0) continue;
          std::vector<double> unit(gains.size(), 0.0);
          unit[k] = 1.0;
          const RowObserver slot(input.width, unit, ShutterMode::kNumerical, params);
          RowObserver::Scratch slot_scratch(slot);
          slot.load_row(input.row(0, y), slot_scratch);
          slot.observe(false, 0, 0, y, slot_scratch, frame);  // max(e_k, 0)
          sampler.accumulate(frame, {77, 0, k, static_cast<std::uint64_t>(y)}, gains[k], sum);
        }
        EXPECT_TRUE(noisy == sum) << name << " velocity " << velocity << " row " << y;
      }
    }
  }
}

TEST(AggregatedNoise, TrialsAreTheRunsOfTheirSeeds) {
  // Trial t of a run with seed s has the noise of a one-trial run with seed
  // s + t, whether it was drawn from its frames (sinc: too many groups for a
  // plan) or replayed (raskar: one group).
  const Image input = test::make_test_image(480, 5, 3, 11);
  for (const char* name : {"sinc", "raskar"}) {
    const ShutterCode code{name, test::paper_gains(name)};
    for (const double velocity : {1.0, -0.45}) {
      SimulationOptions options;
      options.noise = NoiseModel::kAggregated;
      options.velocity_px_per_slot = velocity;
      options.snr = 15.0;
      options.seed = 70;
      double rmse_sum = 0.0, ci_sum = 0.0;
      for (int t = 0; t < 3; ++t) {
        options.seed = 70 + static_cast<std::uint64_t>(t);
        const Metrics m = Simulate(options, input, code).metrics;
        rmse_sum += m.rmse;
        ci_sum += m.rmse_ci;
      }
      options.seed = 70;
      options.trials = 3;
      const TrialStatistics trials = Simulate(options, input, code).trials;
      EXPECT_EQ(trials.rmse_mean, rmse_sum / 3) << "velocity " << velocity;
      EXPECT_EQ(trials.rmse_ci_mean, ci_sum / 3) << name << " velocity " << velocity;
    }
  }
}

// A campaign directory is resumed only by the campaign of its hash: the
// aggregated sampler's version is in an aggregated campaign's hash (so that
// one written before the groups is not resumed with other draws), and in no
// other campaign's, whose hash and canonical form stay as they were.
TEST(AggregatedNoise, SamplerVersionIsInTheHashOfAggregatedCampaignsOnly) {
  CampaignSpec spec;
  spec.inputs = {test::source_path("data/camera.png")};
  spec.codes = {"raskar"};
  const ResolvedCampaign poisson = resolve_campaign(spec);
  EXPECT_EQ(poisson.canonical_json.find("aggregated_sampler"), std::string::npos);
  spec.noise = NoiseModel::kAggregated;
  const ResolvedCampaign aggregated = resolve_campaign(spec);
  EXPECT_EQ(aggregated.aggregated_sampler, kAggregatedSamplerVersion);
  EXPECT_NE(aggregated.canonical_json.find("\"aggregated_sampler\":2"), std::string::npos);
  EXPECT_EQ(campaign_from_canonical_json(aggregated.canonical_json).sha256, aggregated.sha256);
  // A journal of version 1 (no key) reads back as version 1, with its own hash.
  std::string old_json = aggregated.canonical_json;
  const std::string key = "\"aggregated_sampler\":2,";
  old_json.erase(old_json.find(key), key.size());
  const ResolvedCampaign old = campaign_from_canonical_json(old_json);
  EXPECT_EQ(old.aggregated_sampler, 1);
  EXPECT_EQ(old.canonical_json, old_json);
  EXPECT_NE(old.sha256, aggregated.sha256);
  // An unknown version is refused.
  std::string future = aggregated.canonical_json;
  future.replace(future.find(key), key.size(), "\"aggregated_sampler\":3,");
  EXPECT_TRUE(test::throws_error([&] { campaign_from_canonical_json(future); }, ErrorKind::kRuntime,
                                 {"aggregated_sampler"}));
}

// ---------------------------------------------------------------------------
// Per-pixel mean and variance maps of the observation

struct Moments {
  std::vector<double> mean, variance;  // per pixel, sample variance
};

// Moments of the numerical observation of `u` over seeds [0, seeds).
Moments observation_moments(const RowSpectra& u, const std::vector<double>& gains,
                            ReferenceParams params, int seeds) {
  const std::size_t n = static_cast<std::size_t>(u.width) * u.height * u.channels;
  std::vector<double> sum(n, 0.0), sum_sq(n, 0.0);
  for (int s = 0; s < seeds; ++s) {
    params.seed = static_cast<std::uint64_t>(s);
    const Image o = observe_numerical(u, gains, params);
    for (std::size_t i = 0; i < n; ++i) {
      sum[i] += o.data[i];
      sum_sq[i] += o.data[i] * o.data[i];
    }
  }
  Moments m{std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    m.mean[i] = sum[i] / seeds;
    m.variance[i] = (sum_sq[i] - seeds * m.mean[i] * m.mean[i]) / (seeds - 1);
  }
  return m;
}

// The exact per-pixel variance of the numerical observation,
// sum_k alpha_k^2 Var(PoissonSNR(e_k)) (docs/method.md §6b), from each
// slot's noise-free observation max(e_k, 0), and the aggregated sampler's,
// whose grouped frames have no rounding term (docs/method.md §6c); and how
// many pixel frames are on each branch.
struct ExactVariance {
  std::vector<double> variance;
  std::vector<double> aggregated;
  int knuth_frames = 0;
  int normal_frames = 0;
};

ExactVariance exact_variance(const RowSpectra& u, const std::vector<double>& gains,
                             const ReferenceParams& params) {
  const double lambda2 = params.snr * params.snr / 100.0;
  ExactVariance exact;
  exact.variance.assign(static_cast<std::size_t>(u.width) * u.height * u.channels, 0.0);
  exact.aggregated = exact.variance;
  const std::vector<int> groups = gain_groups(gains);
  for (std::size_t k = 0; k < gains.size(); ++k) {
    if (gains[k] == 0.0) continue;
    std::vector<double> unit(gains.size(), 0.0);
    unit[k] = 1.0;
    const Image e = observe_noise_free(u, unit, ShutterMode::kNumerical, params);
    for (std::size_t i = 0; i < exact.variance.size(); ++i) {
      const double alpha2 = gains[k] * gains[k];
      exact.variance[i] += alpha2 * poisson_snr_variance(e.data[i], lambda2);
      exact.aggregated[i] +=
          alpha2 * (groups[k] == kSingleFrame ? poisson_snr_variance(e.data[i], lambda2)
                                              : std::max(e.data[i], 0.0) / lambda2);
      (e.data[i] * lambda2 < kKnuthLimit ? exact.knuth_frames : exact.normal_frames) += 1;
    }
  }
  return exact;
}

struct MapCase {
  const char* code;
  double velocity;
  double snr;
};

class ObservationMaps : public ::testing::TestWithParam<MapCase> {};

// Both samplers' mean maps agree with E[o] and their variance maps with the
// exact variance, pixel by pixel within sampling error and pooled within a
// few standard errors of the pooled statistic; and with each other.
TEST_P(ObservationMaps, AgreeWithThePerFrameSamplerAndTheExactMoments) {
  const MapCase c = GetParam();
  constexpr int kSeeds = 600;
  // Levels 10 to 240: lambda from 10 lambda2 up (at least 2.5 here), so
  // that Knuth's frames are not too skewed: a pixel's excess kurtosis is at
  // most 0.1 with its tens of frames.
  Image input = test::make_test_image(96, 4, 1, 3);
  for (double& value : input.data) value = 10.0 + 0.9 * value;
  const RowSpectra u = row_spectra(input, 1);
  const std::vector<double> gains = test::paper_gains(c.code);
  ReferenceParams params;
  params.velocity = c.velocity;
  params.snr = c.snr;
  const Image expectation = observe_noise_free(u, gains, ShutterMode::kNumerical, params);
  const ExactVariance exact = exact_variance(u, gains, params);
  EXPECT_GT(exact.knuth_frames, 0);
  EXPECT_GT(exact.normal_frames, 0);
  const Moments per_frame = observation_moments(u, gains, params, kSeeds);
  params.aggregate_noise = true;
  const Moments aggregated = observation_moments(u, gains, params, kSeeds);

  const std::vector<double>& variance = exact.variance;
  const std::size_t n = variance.size();
  const std::vector<double>& aggregated_variance = exact.aggregated;
  // Standard error of a sample variance: sigma^2 sqrt(2 / (S - 1) + kappa / S),
  // kappa the excess kurtosis, at most 0.1 here.
  const double variance_relative_se = std::sqrt(2.0 / (kSeeds - 1) + 0.1 / kSeeds);
  double mean_z2 = 0.0, between_z2 = 0.0, ratio_aggregated = 0.0, ratio_per_frame = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_GT(variance[i], 0.0);
    const double se = std::sqrt(aggregated_variance[i] / kSeeds);
    const double z = (aggregated.mean[i] - expectation.data[i]) / se;
    EXPECT_LT(std::abs(z), 4.5) << "pixel " << i << " mean " << aggregated.mean[i] << " vs "
                                << expectation.data[i];
    mean_z2 += z * z;
    const double between = (aggregated.mean[i] - per_frame.mean[i]) / (std::sqrt(2.0) * se);
    between_z2 += between * between;
    ratio_aggregated += aggregated.variance[i] / aggregated_variance[i];
    ratio_per_frame += per_frame.variance[i] / variance[i];
    EXPECT_NEAR(aggregated.variance[i] / aggregated_variance[i], 1.0, 4.5 * variance_relative_se)
        << "pixel " << i;
    EXPECT_NEAR(per_frame.variance[i] / variance[i], 1.0, 4.5 * variance_relative_se)
        << "pixel " << i;
  }
  // Pooled over the n independent pixels: the mean of z^2 is 1 within 4
  // sqrt(2 / n), the mean variance ratio 1 within 4 of its standard errors.
  const double count = static_cast<double>(n);
  EXPECT_NEAR(mean_z2 / count, 1.0, 4.0 * std::sqrt(2.0 / count));
  EXPECT_NEAR(between_z2 / count, 1.0, 4.0 * std::sqrt(2.0 / count));
  EXPECT_NEAR(ratio_aggregated / count, 1.0, 4.0 * variance_relative_se / std::sqrt(count));
  EXPECT_NEAR(ratio_per_frame / count, 1.0, 4.0 * variance_relative_se / std::sqrt(count));
}

INSTANTIATE_TEST_SUITE_P(Codes, ObservationMaps,
                         ::testing::Values(MapCase{"raskar", 1.0, 6.0}, MapCase{"mip", 0.7, 8.0},
                                           MapCase{"sinc", -1.3, 6.0}),
                         [](const auto& info) { return std::string(info.param.code); });

// ---------------------------------------------------------------------------
// RMSE and RMSE_CI over many trials, every code of the paper

// A 300 x 8 crop of camera.png (columns 100..399, rows 200..207): wide
// enough for L = 52 with a 20-column RMSE margin (RMSE over 104 columns,
// RMSE_CI over 40), small enough for a fast suite.
Image camera_crop() {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(300, 8, 1);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 200 + y, 100 + x);
  }
  return crop;
}

struct TrialCase {
  const char* code;
  double snr;
  std::vector<std::uint64_t> seeds;
};

class TrialMeans : public ::testing::TestWithParam<TrialCase> {};

// The means over 100 trials of RMSE and of RMSE_CI agree between the two
// samplers, and the aggregated run's exact prediction, sqrt(E[MSE]), is the
// Monte Carlo estimate sqrt(mean RMSE^2) (E[MSE] = mean^2 + sd^2 (n - 1) / n,
// standard error about sd / sqrt(n) by the delta method on RMSE^2): each
// within 3 standard errors, pooled over the case's seeds (the sum of the
// seeds' differences over the square root of the sum of their variances;
// the two samplers use separate streams, so their trials are independent).
TEST_P(TrialMeans, AgreeWithThePerFrameSampler) {
  const TrialCase c = GetParam();
  static const Image input = camera_crop();
  const ShutterCode code{c.code, test::paper_gains(c.code)};
  const double n = test::kAddressSanitizer ? 20 : 100;  // ASan: the same paths, fewer trials
  struct Pooled {
    double difference = 0.0, variance = 0.0;
    void add(double d, double se) {
      difference += d;
      variance += se * se;
    }
    double z() const { return difference / std::sqrt(variance); }
  } rmse, rmse_ci, prediction;
  bool predicted = true;
  for (const std::uint64_t seed : c.seeds) {
    SimulationOptions options;
    options.snr = c.snr;
    options.trials = static_cast<int>(n);
    options.rmse_margin_columns = 20;
    options.seed = seed;
    const TrialStatistics per_frame = Simulate(options, input, code).trials;
    options.noise = NoiseModel::kAggregated;
    const SimulationReport report = Simulate(options, input, code);
    const TrialStatistics& aggregated = report.trials;
    const double rmse_se = std::sqrt(
        (per_frame.rmse_sd * per_frame.rmse_sd + aggregated.rmse_sd * aggregated.rmse_sd) / n);
    const double ci_se = std::sqrt((per_frame.rmse_ci_sd * per_frame.rmse_ci_sd +
                                    aggregated.rmse_ci_sd * aggregated.rmse_ci_sd) /
                                   n);
    ASSERT_GT(rmse_se, 0.0);
    ASSERT_GT(ci_se, 0.0);
    rmse.add(aggregated.rmse_mean - per_frame.rmse_mean, rmse_se);
    rmse_ci.add(aggregated.rmse_ci_mean - per_frame.rmse_ci_mean, ci_se);
    predicted = predicted && report.prediction.finite;  // accumulation: K vanishes
    if (!predicted) continue;
    const double mean_mse = aggregated.rmse_mean * aggregated.rmse_mean +
                            aggregated.rmse_sd * aggregated.rmse_sd * (n - 1.0) / n;
    prediction.add(report.prediction.rmse - std::sqrt(mean_mse), aggregated.rmse_sd / std::sqrt(n));
  }
  RecordProperty("rmse_z", std::to_string(rmse.z()));
  RecordProperty("rmse_ci_z", std::to_string(rmse_ci.z()));
  EXPECT_LT(std::abs(rmse.z()), 3.0) << "RMSE: aggregated - per-frame " << rmse.difference;
  EXPECT_LT(std::abs(rmse_ci.z()), 3.0) << "RMSE_CI: aggregated - per-frame " << rmse_ci.difference;
  if (!predicted) return;
  RecordProperty("prediction_z", std::to_string(prediction.z()));
  EXPECT_LT(std::abs(prediction.z()), 3.0) << "predicted - measured " << prediction.difference;
}

// Every code of the paper; three seeds for raskar (one group) and sinc (23
// groups and a single frame), two for the others.
std::vector<TrialCase> trial_cases() {
  std::vector<TrialCase> cases;
  for (const char* name : {"snapshot", "accumulation", "raskar", "random", "mip", "sinc"}) {
    const std::string code = name;
    std::vector<std::uint64_t> seeds = {1000, 5000};
    if (code == "raskar" || code == "sinc") seeds = {1000, 5000, 9000};
    for (const double snr : {5.0, 100.0}) cases.push_back({name, snr, seeds});
  }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(PaperCodes, TrialMeans, ::testing::ValuesIn(trial_cases()),
                         [](const auto& info) {
                           return std::string(info.param.code) + "_snr" +
                                  std::to_string(static_cast<int>(info.param.snr));
                         });

}  // namespace
}  // namespace fss
