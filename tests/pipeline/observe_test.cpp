// Tests of the flutter shutter observation (observe.h and the whole-image
// reference paths, docs/method.md §2 and §3).
#include "pipeline/observe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <ostream>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"
#include "support/reference_paths.h"
#include "support/test_util.h"

namespace fss {
namespace {

std::vector<double> code_gains(const char* name) { return builtin_code(name).value().gains; }

ReferenceParams make_params(double velocity, double dt, double snr, std::uint64_t seed,
                            int threads) {
  ReferenceParams p;
  p.velocity = velocity;
  p.dt = dt;
  p.snr = snr;
  p.seed = seed;
  p.threads = threads;
  return p;
}

bool bit_identical(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels &&
         a.data.size() == b.data.size() &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(double)) == 0;
}

// Gains with 1 at slot k and 0 elsewhere: the elementary exposure K_k.
std::vector<double> slot_code(int k, int length) {
  std::vector<double> gains(static_cast<std::size_t>(length), 0.0);
  gains[static_cast<std::size_t>(k)] = 1.0;
  return gains;
}

// 100 + 50 sin(2 pi 3 x / W) + a gentle vertical variation: band-limited, so
// every elementary exposure stays far above 0.
Image smooth_image(int width, int height, int channels) {
  Image image(width, height, channels);
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        image.at(c, y, x) = 100.0 + 50.0 * std::sin(2.0 * M_PI * 3.0 * x / width + 0.5 * c) +
                            10.0 * std::cos(0.2 * y);
      }
    }
  }
  return image;
}

// Dark bars with bright neighbours: the band-limited interpolation rings below 0.
Image dark_edges_image(int width, int height) {
  Image image(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) image.at(0, y, x) = ((x / 9 + y) % 3 == 0) ? 255.0 : 0.0;
  }
  return image;
}

struct Moments {
  double mean = 0.0;
  double variance = 0.0;     // unbiased
  double mean_se = 0.0;      // standard error of the mean
  double variance_se = 0.0;  // standard error of the variance, from the 4th moment
};

Moments moments(const Samples& values) {
  const double n = static_cast<double>(values.size());
  Moments m;
  m.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double m2 = 0.0, m4 = 0.0;
  for (const double v : values) {
    const double d = v - m.mean;
    m2 += d * d;
    m4 += d * d * d * d;
  }
  m.variance = m2 / (n - 1.0);
  m2 /= n;
  m4 /= n;
  m.mean_se = std::sqrt(m.variance / n);
  m.variance_se = std::sqrt(std::max(m4 - m2 * m2, 0.0) / n);
  return m;
}

// ---------------------------------------------------------------------------
// Noise-free convolution.

TEST(ConvolveRows, ConstantImageGivesKZeroTimesTheLevel) {
  struct Case {
    const char* code;
    double velocity, dt;
  };
  for (const Case& c : {Case{"raskar", 1.0, 1.0}, Case{"random", 0.7, 1.3}, Case{"mip", -1.0, 1.0},
                        Case{"snapshot", 2.5, 0.5}}) {
    const std::vector<double> gains = code_gains(c.code);
    const double level = 37.0;
    const Image input(64, 3, 2, level);
    const Image e =
        convolve_rows(row_spectra(input, 1), gains, make_params(c.velocity, c.dt, 100.0, 0, 2));
    ASSERT_EQ(e.width, 64);
    ASSERT_EQ(e.height, 3);
    ASSERT_EQ(e.channels, 2);
    double k0 = 0.0;
    for (const double g : gains) k0 += c.dt * g;
    for (const double v : e.data) {
      // FFT round-off on values of order 52 * 37.
      ASSERT_NEAR(v, k0 * level, 1e-9) << c.code;
    }
  }
}

TEST(ConvolveRows, ImpulseGivesTheKernelShiftedByTheMotion) {
  // At v = 1, dt = 1 the snapshot code integrates the scene over one pixel of
  // motion: a smooth bump comes out translated by half a pixel (the half in
  // k + 1/2), so its centre of mass moves by +0.5 column.
  const int width = 128;
  Image input(width, 1, 1);
  for (int x = 0; x < width; ++x)
    input.at(0, 0, x) = std::exp(-0.5 * std::pow((x - 64.0) / 4.0, 2));
  const Image e = convolve_rows(row_spectra(input, 1), code_gains("snapshot"),
                                make_params(1.0, 1.0, 100.0, 0, 1));
  auto centre = [](const Image& image) {
    double s = 0.0, sx = 0.0;
    for (int x = 0; x < image.width; ++x) {
      s += image.at(0, 0, x);
      sx += x * image.at(0, 0, x);
    }
    return sx / s;
  };
  // A Gaussian of sd 4 is band-limited to double precision on this grid.
  EXPECT_NEAR(centre(e) - centre(input), 0.5, 1e-6);
}

TEST(ObserveNoiseFree, AnalogIsTheClippedConvolution) {
  const RowSpectra u = row_spectra(dark_edges_image(128, 6), 1);
  const ReferenceParams p = make_params(1.0, 1.0, 100.0, 0, 2);
  int negatives = 0;
  for (const char* name : {"snapshot", "raskar"}) {
    const std::vector<double> gains = code_gains(name);
    const Image e = convolve_rows(u, gains, p);
    negatives += static_cast<int>(
        std::count_if(e.data.begin(), e.data.end(), [](double v) { return v < 0.0; }));
    const Image o = observe_noise_free(u, gains, ShutterMode::kAnalog, p);
    ASSERT_EQ(o.data.size(), e.data.size());
    for (std::size_t i = 0; i < e.data.size(); ++i) {
      // Same FFTs on both sides: only round-off may differ.
      ASSERT_NEAR(o.data[i], std::max(e.data[i], 0.0), 1e-9) << name << " " << i;
    }
  }
  // The snapshot code's one-pixel blur rings below 0 next to the dark bars.
  EXPECT_GT(negatives, 0) << "nothing to clip: the test does not test the clip";
}

TEST(ObserveNoiseFree, NumericalIsTheSumOfClippedSlotExposures) {
  for (const char* name : {"raskar", "random"}) {
    const std::vector<double> gains = code_gains(name);
    const int length = static_cast<int>(gains.size());
    const RowSpectra u = row_spectra(dark_edges_image(96, 4), 1);
    const ReferenceParams p = make_params(1.0, 1.0, 100.0, 0, 2);
    Image expected(96, 4, 1);
    bool clipped = false;
    for (int k = 0; k < length; ++k) {
      const Image e_k = convolve_rows(u, slot_code(k, length), p);
      for (std::size_t i = 0; i < e_k.data.size(); ++i) {
        clipped = clipped || (gains[k] != 0.0 && e_k.data[i] < 0.0);
        expected.data[i] += gains[k] * std::max(e_k.data[i], 0.0);
      }
    }
    ASSERT_TRUE(clipped) << "the test image should ring below 0, or the clip is not tested";
    const Image o = observe_noise_free(u, gains, ShutterMode::kNumerical, p);
    // Round-off of 52 FFT rows summed, values of order 52 * 255.
    EXPECT_LT(test::max_abs_difference(o, expected), 1e-9) << name;
  }
}

TEST(ObserveNoiseFree, NumericalEqualsTheConvolutionForASmoothImage) {
  // Nothing is clipped, so by linearity sum_k alpha_k e_k = rowconv(u, K).
  for (const char* name : {"raskar", "random", "mip"}) {
    const std::vector<double> gains = code_gains(name);
    for (const Image& input : {smooth_image(128, 5, 2), Image(128, 5, 2, 42.0)}) {
      const RowSpectra u = row_spectra(input, 1);
      const ReferenceParams p = make_params(0.8, 1.1, 100.0, 0, 2);
      const Image o = observe_noise_free(u, gains, ShutterMode::kNumerical, p);
      // Round-off of 52 FFT rows summed, values of order 52 * 160.
      EXPECT_LT(test::max_abs_difference(o, convolve_rows(u, gains, p)), 1e-9) << name;
    }
  }
}

// The variance row of the noise-free observation (docs/method.md §6b), against
// each pixel's variance computed by brute force: every slot's exposure e_k by
// its own convolution, Var(o) = sum_k alpha_k^2 Var(PoissonSNR(e_k)) (analog:
// Var(PoissonSNR(e))), Var as poisson_snr_variance.
struct VarianceCase {
  const char* code;
  ShutterMode mode;
  double velocity;  // 1: the numerical mode's shifts; 0.37: one transform per slot
  double dt;
  double snr;
};

class ObserveVariance : public ::testing::TestWithParam<VarianceCase> {};

TEST_P(ObserveVariance, IsEachPixelsVarianceComputedSlotBySlot) {
  const VarianceCase& c = GetParam();
  const std::vector<double> gains = code_gains(c.code);
  const int length = static_cast<int>(gains.size());
  const Image input = dark_edges_image(120, 3);
  const RowSpectra u = row_spectra(input, 1);
  const ReferenceParams p = make_params(c.velocity, c.dt, c.snr, 0, 1);
  const double lambda2 = PoissonSNR(c.snr).lambda2();
  // Brute force, and which branches of the sampler it went through.
  Image expected(120, 3, 1);
  int clipped = 0, knuth = 0, normal = 0;
  const auto add = [&](const Image& e, double weight) {
    for (std::size_t i = 0; i < e.data.size(); ++i) {
      if (weight == 0.0) continue;
      expected.data[i] += weight * poisson_snr_variance(e.data[i], lambda2);
      clipped += e.data[i] < 0.0 ? 1 : 0;
      (std::max(e.data[i], 0.0) * lambda2 < kKnuthLimit ? knuth : normal) += 1;
    }
  };
  if (c.mode == ShutterMode::kAnalog) {
    add(convolve_rows(u, gains, p), 1.0);
  } else {
    for (int k = 0; k < length; ++k)
      add(convolve_rows(u, slot_code(k, length), p), gains[k] * gains[k]);
  }
  EXPECT_GT(clipped, 0);
  EXPECT_GT(knuth, 0);
  EXPECT_GT(normal, 0);
  // The observer's variance row, and its expectation unchanged by asking for it.
  const RowObserver observer(120, gains, c.mode, p);
  RowObserver::Scratch scratch(observer);
  std::vector<double> out(120), plain(120), variance(120, -1.0);
  double largest = 0.0;
  for (int y = 0; y < 3; ++y) {
    observer.load_row(input.row(0, y), scratch);
    observer.observe(false, 0, 0, y, scratch, plain);
    observer.observe(false, 0, 0, y, scratch, out, variance);
    EXPECT_EQ(out, plain);
    for (int x = 0; x < 120; ++x) {
      largest = std::max(largest, expected.at(0, y, x));
      // Round-off of the FFT exposures only (relative 1e-12 of the row's scale).
      ASSERT_NEAR(variance[x], expected.at(0, y, x), 1e-11 * (1.0 + largest))
          << c.code << " y " << y << " x " << x;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Modes, ObserveVariance,
    ::testing::Values(VarianceCase{"mip", ShutterMode::kNumerical, 1.0, 1.0, 5.0},
                      VarianceCase{"raskar", ShutterMode::kNumerical, -1.0, 1.0, 200.0},
                      VarianceCase{"random", ShutterMode::kNumerical, 0.37, 1.0, 200.0},
                      VarianceCase{"mip", ShutterMode::kNumerical, -0.73, 0.5, 100.0},
                      VarianceCase{"snapshot", ShutterMode::kAnalog, 1.0, 1.0, 5.0},
                      VarianceCase{"raskar", ShutterMode::kAnalog, 0.37, 0.5, 200.0}),
    [](const auto& info) {
      return std::string(info.param.code) + "_" + to_string(info.param.mode) + "_" +
             std::to_string(info.index);
    });

// ---------------------------------------------------------------------------
// Noisy observations: validation, reproducibility and statistics.

TEST(ObserveAnalog, RefusesGainsOutsideTheUnitInterval) {
  const RowSpectra u = row_spectra(Image(32, 2, 1, 10.0), 1);
  const ReferenceParams p = make_params(1.0, 1.0, 100.0, 0, 1);
  const std::vector<std::vector<double>> bad = {
      {0.5, 1.2}, {-0.1, 1.0}, {1.0, 0.0, -1.0}, {0.3, std::nan("")}};
  for (const auto& gains : bad) {
    EXPECT_TRUE(
        test::throws_error([&] { observe_analog(u, gains, p); }, ErrorKind::kUsage, {"gain"}));
  }
  // The bounds themselves are allowed.
  EXPECT_NO_THROW(observe_analog(u, std::vector<double>{0.0, 1.0, 0.5}, p));
}

TEST(ObserveNoisy, ThreadCountDoesNotChangeTheResult) {
  const Image input = test::make_test_image(96, 17, 3, 2);
  const RowSpectra u1 = row_spectra(input, 1);
  const RowSpectra u3 = row_spectra(input, 3);
  ASSERT_EQ(u1.bins.size(), u3.bins.size());
  EXPECT_EQ(std::memcmp(u1.bins.data(), u3.bins.data(), u1.bins.size() * sizeof(u1.bins[0])), 0);
  const std::vector<double> raskar = code_gains("raskar");
  const std::vector<double> random = code_gains("random");
  EXPECT_TRUE(bit_identical(observe_numerical(u1, random, make_params(1.0, 1.0, 30.0, 9, 1)),
                            observe_numerical(u1, random, make_params(1.0, 1.0, 30.0, 9, 3))));
  EXPECT_TRUE(bit_identical(observe_analog(u1, raskar, make_params(1.0, 1.0, 30.0, 9, 1)),
                            observe_analog(u1, raskar, make_params(1.0, 1.0, 30.0, 9, 3))));
}

TEST(ObserveNoisy, SameSeedSameResultOtherSeedOtherResult) {
  const RowSpectra u = row_spectra(test::make_test_image(64, 8, 1, 3), 1);
  const std::vector<double> raskar = code_gains("raskar");
  const auto numerical = [&](std::uint64_t seed) {
    return observe_numerical(u, raskar, make_params(1.0, 1.0, 50.0, seed, 2));
  };
  const auto analog = [&](std::uint64_t seed) {
    return observe_analog(u, raskar, make_params(1.0, 1.0, 50.0, seed, 2));
  };
  EXPECT_TRUE(bit_identical(numerical(5), numerical(5)));
  EXPECT_FALSE(bit_identical(numerical(5), numerical(6)));
  EXPECT_TRUE(bit_identical(analog(5), analog(5)));
  EXPECT_FALSE(bit_identical(analog(5), analog(6)));
}

TEST(ObserveNoisy, ChannelsGetIndependentNoise) {
  // Three identical channels must not receive the same noise.
  const Image gray = test::make_test_image(64, 8, 1, 3);
  Image rgb(64, 8, 3);
  for (int c = 0; c < 3; ++c) std::copy(gray.data.begin(), gray.data.end(), rgb.row(c, 0));
  const Image o = observe_numerical(row_spectra(rgb, 1), code_gains("raskar"),
                                    make_params(1.0, 1.0, 50.0, 1, 1));
  const std::size_t plane = o.plane_size();
  EXPECT_FALSE(std::equal(o.data.begin(), o.data.begin() + plane, o.data.begin() + plane));
}

struct StatisticsCase {
  const char* name;
  const char* code;
  ShutterMode mode;
  double snr;
};

void PrintTo(const StatisticsCase& c, std::ostream* os) { *os << c.name; }

class ObservationStatistics : public ::testing::TestWithParam<StatisticsCase> {};

// A constant landscape at level 100 seen at v = 0: every pixel of the
// observation is an independent draw with mean 100 K(0) = 100 dt sum alpha
// and variance 100 Q (100 / snr^2), Q = dt sum alpha^2 (numerical) or
// dt sum alpha (analog).
TEST_P(ObservationStatistics, MeanAndVarianceFollowTheTheory) {
  const StatisticsCase& c = GetParam();
  const std::vector<double> gains = code_gains(c.code);
  const double dt = 1.0;
  double sum = 0.0, sum_sq = 0.0;
  for (const double g : gains) {
    sum += g;
    sum_sq += g * g;
  }
  const double q = c.mode == ShutterMode::kNumerical ? dt * sum_sq : dt * sum;
  const double expected_mean = 100.0 * dt * sum;
  const double expected_variance = 100.0 * q * 100.0 / (c.snr * c.snr);

  const RowSpectra u = row_spectra(Image(256, 256, 1, 100.0), 2);
  const ReferenceParams p = make_params(0.0, dt, c.snr, 12345, 2);
  const Image o = c.mode == ShutterMode::kNumerical ? observe_numerical(u, gains, p)
                                                    : observe_analog(u, gains, p);
  const Moments m = moments(o.data);
  // 5 standard errors: a correct implementation fails with probability < 1e-6.
  EXPECT_NEAR(m.mean, expected_mean, 5.0 * m.mean_se) << c.name;
  EXPECT_NEAR(m.variance, expected_variance, 5.0 * m.variance_se) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Codes, ObservationStatistics,
    ::testing::Values(
        // lambda = 100 * snr^2 / 100 = 10^4: the normal branch of the Poisson draw.
        StatisticsCase{"NumericalSnapshot", "snapshot", ShutterMode::kNumerical, 100.0},
        // lambda = 25 < 50: Knuth's branch.
        StatisticsCase{"NumericalSnapshotLowSnr", "snapshot", ShutterMode::kNumerical, 5.0},
        // Signed gains: the variance adds alpha_k^2 times that of each slot.
        StatisticsCase{"NumericalRandom", "random", ShutterMode::kNumerical, 100.0},
        StatisticsCase{"AnalogRaskar", "raskar", ShutterMode::kAnalog, 100.0},
        StatisticsCase{"AnalogRaskarLowSnr", "raskar", ShutterMode::kAnalog, 1.0}),
    [](const ::testing::TestParamInfo<StatisticsCase>& info) { return info.param.name; });

TEST(ObservationStatistics, NegativeExpectationGivesZero) {
  // PoissonSNR(e) draws from max(e, 0): a landscape at -5 is observed as 0.
  const RowSpectra u = row_spectra(Image(32, 4, 1, -5.0), 1);
  const Image o = observe_analog(u, code_gains("raskar"), make_params(0.0, 1.0, 100.0, 1, 1));
  for (const double v : o.data) ASSERT_EQ(v, 0.0);
}

}  // namespace
}  // namespace fss
