// Tests of the geometry, the mirror extension and the inverse filter
// (geometry.h, restore.h and the whole-image reference paths, docs/method.md §4).
#include "pipeline/restore.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/fft.h"
#include "fss/core/error.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/model/transfer.h"
#include "pipeline/observe.h"
#include "support/reference_paths.h"
#include "support/test_util.h"

namespace fss {
namespace {

std::vector<double> raskar() { return builtin_code("raskar").value().gains; }
std::vector<double> random_code() { return builtin_code("random").value().gains; }

// Uniform values in [0, 255).
Image random_image(int width, int height, int channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(0.0, 255.0);
  Image image(width, height, channels);
  for (double& v : image.data) v = value(rng);
  return image;
}

// Circular convolution of every row with K on the row's own N-point grid.
Image convolve_on_own_grid(const Image& image, const std::vector<double>& gains, double velocity,
                           double dt) {
  const int n = image.width;
  const RowFFT fft(n);
  RowFFT::Workspace workspace(n);
  const std::vector<Complex> k = transfer_function_bins(gains, velocity, dt, n);
  Image out(n, image.height, image.channels);
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      std::copy(image.row(c, y), image.row(c, y) + n, workspace.real().begin());
      fft.forward(workspace);
      multiply_half_spectrum(workspace.spectrum(), k, n);
      fft.inverse(workspace);
      for (int x = 0; x < n; ++x) out.at(c, y, x) = workspace.real()[x] / n;
    }
  }
  return out;
}

// Geometry::compute(width, code_length, velocity, dt) throws a usage error.
::testing::AssertionResult geometry_refused(int width, int code_length, double velocity,
                                            double dt) {
  return test::throws_error([&] { Geometry::compute(width, code_length, velocity, dt); },
                            ErrorKind::kUsage);
}

// ---------------------------------------------------------------------------
// Geometry.

// A code whose gains sum to 0 has K(0) = 0 exactly: the restorer counts that
// bin (and Simulate warns about it). zero_bins_ was once reset after being
// counted, by the order of the members' initializers.
TEST(RowRestorer, CountsTheZeroBinsOfK) {
  const std::vector<double> gains = {1.0, -1.0};
  const Geometry g = Geometry::compute(64, static_cast<int>(gains.size()), 1.0, 1.0);
  const RowRestorer zero_mean(g, gains, 1.0, 1.0);
  EXPECT_GE(zero_mean.zero_bins(), 1);
  const std::vector<double> snapshot = {1.0, 0.0};
  EXPECT_EQ(RowRestorer(g, snapshot, 1.0, 1.0).zero_bins(), 0);
}

TEST(Geometry, ReferenceCase) {
  const Geometry g = Geometry::compute(512, 52, 1.0, 1.0);
  EXPECT_EQ(g.width, 512);
  EXPECT_EQ(g.blur_length, 52);
  EXPECT_EQ(g.half_blur, 26);
  EXPECT_EQ(g.observed_width, 460);
  EXPECT_EQ(g.mirror_width, 920);
  EXPECT_EQ(g.output_width, 356);
}

TEST(Geometry, SlowMotionKeepsTheCodeLength) {
  for (const double v : {0.0, 0.5, -0.5, -1.0}) {
    const Geometry g = Geometry::compute(512, 52, v, 1.0);
    EXPECT_EQ(g.blur_length, 52) << "v = " << v;
    EXPECT_EQ(g.output_width, 356) << "v = " << v;
  }
  // |v| dt = 0.5 * 2 = 1: still the code length.
  EXPECT_EQ(Geometry::compute(512, 52, 0.5, 2.0).blur_length, 52);
}

TEST(Geometry, FastMotionLengthensTheBlur) {
  for (const double v : {2.0, -2.0}) {
    const Geometry g = Geometry::compute(512, 52, v, 1.0);
    EXPECT_EQ(g.blur_length, 104) << "v = " << v;  // |v| dt L = 104
    EXPECT_EQ(g.half_blur, 52) << "v = " << v;
    EXPECT_EQ(g.observed_width, 408) << "v = " << v;
    EXPECT_EQ(g.mirror_width, 816) << "v = " << v;
    EXPECT_EQ(g.output_width, 200) << "v = " << v;
  }
  // |v| dt L = 1 * 1.5 * 52 = 78
  EXPECT_EQ(Geometry::compute(512, 52, 1.0, 1.5).blur_length, 78);
}

TEST(Geometry, BlurLengthIsRoundedUp) {
  const Geometry g = Geometry::compute(512, 52, 1.01, 1.0);
  EXPECT_EQ(g.blur_length, 53);  // ceil(52.52)
  EXPECT_EQ(g.half_blur, 26);
  EXPECT_EQ(g.observed_width, 459);
  EXPECT_EQ(g.mirror_width, 918);
  EXPECT_EQ(g.output_width, 512 - 159);
}

TEST(Geometry, NarrowestWidthThatHasAnOutput) {
  const Geometry g = Geometry::compute(157, 52, 1.0, 1.0);
  EXPECT_EQ(g.output_width, 1);
}

TEST(Geometry, TooNarrowIsAUsageError) {
  EXPECT_TRUE(geometry_refused(156, 52, 1.0, 1.0));  // Wo = 0
  EXPECT_TRUE(geometry_refused(100, 52, 1.0, 1.0));
  EXPECT_TRUE(geometry_refused(52, 52, 1.0, 1.0));
  EXPECT_TRUE(geometry_refused(10, 52, 1.0, 1.0));
  EXPECT_TRUE(geometry_refused(311, 52, 2.0, 1.0));   // 3B = 312
  EXPECT_TRUE(geometry_refused(512, 52, 10.0, 1.0));  // blur 520 > W
  EXPECT_TRUE(geometry_refused(512, 0, 1.0, 1.0));    // no gains
}

// ---------------------------------------------------------------------------
// Mirror extension.

TEST(MirrorExtend, MatchesItsDefinition) {
  const Image crop = random_image(7, 3, 2, 11);
  const Image m = mirror_extend(crop);
  ASSERT_EQ(m.width, 14);
  ASSERT_EQ(m.height, 3);
  ASSERT_EQ(m.channels, 2);
  const int wa = crop.width;
  for (int c = 0; c < 2; ++c) {
    for (int y = 0; y < 3; ++y) {
      for (int j = 0; j < 2 * wa; ++j) {
        const int source = j < wa ? j : 2 * wa - 1 - j;
        EXPECT_EQ(m.at(c, y, j), crop.at(c, y, source)) << "c " << c << " y " << y << " j " << j;
      }
    }
  }
}

TEST(MirrorExtend, SingleColumn) {
  Image crop(1, 2, 1);
  crop.data = {4.0, 5.0};
  const Image m = mirror_extend(crop);
  ASSERT_EQ(m.width, 2);
  EXPECT_EQ(m.data, (std::vector<double>{4.0, 4.0, 5.0, 5.0}));
}

// ---------------------------------------------------------------------------
// Inverse filter: exact on a mirror-symmetric row convolved on its own grid.
// (A mirror-symmetric row of even length has no Nyquist component, so the
// real-row handling of that bin plays no part and the inversion is exact.)

struct ExactCase {
  const char* name;
  std::vector<double> gains;
  double velocity;
  double dt;
};

class InverseFilterExact : public ::testing::TestWithParam<int> {};

TEST_P(InverseFilterExact, RecoversTheMirroredRow) {
  const std::vector<ExactCase> cases = {
      {"raskar v=1", raskar(), 1.0, 1.0},
      {"random v=0.7 dt=1.3", random_code(), 0.7, 1.3},
      {"raskar v=-1", raskar(), -1.0, 1.0},
  };
  const ExactCase& c = cases[GetParam()];
  SCOPED_TRACE(c.name);
  ASSERT_TRUE(analyze_kernel(c.gains, c.velocity, c.dt).invertible);
  const Image m = mirror_extend(random_image(460, 4, 2, 5 + GetParam()));
  const Image observed = convolve_on_own_grid(m, c.gains, c.velocity, c.dt);
  const Deconvolution d = inverse_filter(observed, c.gains, c.velocity, c.dt, 2);
  EXPECT_EQ(d.zero_bins, 0);
  ASSERT_EQ(d.image.width, 920);
  ASSERT_EQ(d.image.height, 4);
  ASSERT_EQ(d.image.channels, 2);
  // Round-off of two FFT pairs on values <= 255 amplified by max|K| / min|K|
  // stays far below 1e-9.
  EXPECT_LT(test::max_abs_difference(d.image, m), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Codes, InverseFilterExact, ::testing::Values(0, 1, 2));

TEST(InverseFilter, ThreadCountDoesNotChangeTheResult) {
  const Image m = mirror_extend(random_image(100, 9, 1, 3));
  const Image observed = convolve_on_own_grid(m, raskar(), 1.0, 1.0);
  const Deconvolution one = inverse_filter(observed, raskar(), 1.0, 1.0, 1);
  const Deconvolution three = inverse_filter(observed, raskar(), 1.0, 1.0, 3);
  EXPECT_EQ(one.image.data, three.image.data);
}

TEST(InverseFilter, CountsAndZeroesBinsWhereKIsZero) {
  // v = 0: K = dt sum alpha at every bin; a code summing to 0 makes every bin 0.
  const std::vector<double> gains = {1.0, -1.0};
  const Image row = mirror_extend(random_image(8, 1, 1, 2));
  const Deconvolution d = inverse_filter(row, gains, 0.0, 1.0, 1);
  EXPECT_EQ(d.zero_bins, 9);  // bins 0 .. N/2 of N = 16
  for (const double v : d.image.data) EXPECT_EQ(v, 0.0);
}

// ---------------------------------------------------------------------------
// restore(): crops and alignment.

class RestoreCrops : public ::testing::TestWithParam<double> {};

TEST_P(RestoreCrops, OutputsAreTheDocumentedColumns) {
  const double v = GetParam();
  const std::vector<double> gains = raskar();
  const int width = 340;
  const Geometry g = Geometry::compute(width, 52, v, 1.0);
  const int h = g.half_blur;
  const int wo = g.output_width;
  // Observation and input deliberately unrelated: restore() only crops them.
  const Image observation = random_image(width, 5, 2, 21);
  const Image input = random_image(width, 5, 2, 22);
  const Restoration r = restore(observation, input, g, gains, v, 1.0, 2);
  for (const Image* image : {&r.restored, &r.observed, &r.groundtruth}) {
    EXPECT_EQ(image->width, wo);
    EXPECT_EQ(image->height, 5);
    EXPECT_EQ(image->channels, 2);
  }
  const Deconvolution d = inverse_filter(
      mirror_extend(crop_columns(observation, h, g.observed_width)), gains, v, 1.0, 1);
  for (int c = 0; c < 2; ++c) {
    for (int y = 0; y < 5; ++y) {
      for (int x = 0; x < wo; ++x) {
        ASSERT_EQ(r.groundtruth.at(c, y, x), input.at(c, y, x + 3 * h)) << x;
        ASSERT_EQ(r.observed.at(c, y, x), observation.at(c, y, x + 3 * h)) << x;
        // The restorer may transform on a longer length (RowRestorer): the
        // same operator up to round-off.
        ASSERT_NEAR(r.restored.at(c, y, x), d.image.at(c, y, x + 2 * h), 1e-9) << x;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Velocities, RestoreCrops, ::testing::Values(1.0, 1.01, -2.0));

// ---------------------------------------------------------------------------
// RowRestorer's folded convolution: a transform of length M >= Wa + Wo - 1,
// shorter than the grid N = 2 Wa, for the same operator.

TEST(RowRestorer, TransformLengthOfThePapersGeometry) {
  // Wa + Wo - 1 = 460 + 356 - 1 = 815 -> 896 = 2^7 7 (the grid is N = 920).
  EXPECT_EQ(restoration_transform_length(Geometry::compute(512, 52, 1.0, 1.0)), 896);
  // 3948 + 3844 - 1 = 7791 -> 8192 (N = 7896 = 2^3 3 7 47).
  EXPECT_EQ(restoration_transform_length(Geometry::compute(4000, 52, 1.0, 1.0)), 8192);
  // 588 + 484 - 1 = 1071 -> 1152 = 2^7 9.
  EXPECT_EQ(restoration_transform_length(Geometry::compute(640, 52, 1.0, 1.0)), 1152);
}

TEST(RowRestorer, TransformLengthIsLongEnoughFastAndShorterThanTheGrid) {
  for (int width = 160; width < 3000; width += 37) {
    const Geometry g = Geometry::compute(width, 16, 1.0, 1.0);
    const int taps = g.observed_width + g.output_width - 1;
    const int length = restoration_transform_length(g);
    EXPECT_GE(length, taps) << width;
    int odd = length;
    while (odd % 2 == 0) odd /= 2;
    EXPECT_TRUE(odd == 1 || odd == 3 || odd == 5 || odd == 7 || odd == 9 || odd == 15) << length;
    EXPECT_EQ(length % 2, 0) << length;
    // 2^a m with m in {1, 3, 5, 7, 9, 15} are at most 4/3 apart from 8 on.
    EXPECT_LE(3 * length, 4 * taps + 3) << width;
    EXPECT_LT(length, 4 * g.mirror_width / 3 + 2) << width;
  }
}

struct ConvolutionCase {
  int width;
  const char* code;
  double velocity;
  double dt;
};

class RowRestorerConvolution : public ::testing::TestWithParam<ConvolutionCase> {};

// Restored rows of the folded convolution equal the inverse filter on the
// grid (the reference path, exact on a mirrored row: InverseFilterExact),
// columns 2h.. of it, to round-off.
TEST_P(RowRestorerConvolution, EqualsTheInverseFilterOnTheGrid) {
  const ConvolutionCase& p = GetParam();
  const std::vector<double> gains = builtin_code(p.code).value().gains;
  const Geometry g =
      Geometry::compute(p.width, static_cast<int>(gains.size()), std::abs(p.velocity), p.dt);
  const RowRestorer restorer(g, gains, p.velocity, p.dt);
  const Image observation = random_image(p.width, 3, 1, 40 + p.width);
  const Deconvolution d =
      inverse_filter(mirror_extend(crop_columns(observation, g.half_blur, g.observed_width)), gains,
                     p.velocity, p.dt, 1);
  RowRestorer::Scratch scratch(restorer);
  std::vector<double> restored(static_cast<std::size_t>(g.output_width));
  double largest = 0.0;
  for (const double v : d.image.data) largest = std::max(largest, std::abs(v));
  for (int y = 0; y < 3; ++y) {
    restorer.restore(observation.row(0, y), scratch, restored.data());
    for (int x = 0; x < g.output_width; ++x) {
      ASSERT_NEAR(restored[static_cast<std::size_t>(x)], d.image.at(0, y, x + 2 * g.half_blur),
                  1e-13 * largest)
          << "width " << p.width << " row " << y << " column " << x;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Widths, RowRestorerConvolution,
    ::testing::Values(ConvolutionCase{512, "raskar", 1.0, 1.0},        // N 920, M 896
                      ConvolutionCase{512, "mip", 0.37, 1.0},          // fractional velocity
                      ConvolutionCase{700, "random", -0.73, 1.3},      // N = 1296
                      ConvolutionCase{1009, "sinc", 1.0, 0.5},         // N = 1914 = 2 3 11 29
                      ConvolutionCase{700, "raskar", 1.9, 1.0},        // B = 99, N 1202
                      ConvolutionCase{2003, "snapshot", 1.0, 1.0},     // N = 3902 = 2 1951
                      ConvolutionCase{157, "accumulation", 0.9, 1.0},  // Wo = 1
                      ConvolutionCase{640, "raskar", -2.0, 1.0}));     // K(pi) = 0: the grid

TEST(RowRestorer, FoldsWhenKIsWellConditionedOnly) {
  EXPECT_EQ(
      RowRestorer(Geometry::compute(512, 52, 1.0, 1.0), raskar(), 1.0, 1.0).transform_length(),
      896);
  // Raskar just below |v| dt = 2: K(pi) ~ 1e-9 of its scale is no zero, and
  // the folded convolution's round-off would show (sup |1/K| |K(0)| > 1e6),
  // the grid's does not.
  const Geometry fast = Geometry::compute(640, 52, 2.0, 1.0);
  EXPECT_EQ(RowRestorer(fast, raskar(), -1.9999999, 1.0).transform_length(), fast.mirror_width);
  // At v = -2, K(pi) is 0 up to round-off (sinc_h(2 pi)): a zero bin, left out
  // (transfer_vanishes), and the other bins are well conditioned: it folds.
  const RowRestorer at_two(fast, raskar(), -2.0, 1.0);
  EXPECT_EQ(at_two.zero_bins(), 1);
  EXPECT_EQ(at_two.transform_length(), restoration_transform_length(fast));
  // Accumulation at v = 1 (zeros of K at 2 pi m / 52): on N = 920 the zeros
  // m = 13 and 26 are bins, left out; the nearest other bins are well
  // conditioned enough to fold.
  const std::vector<double> ones(52, 1.0);
  const Geometry slow = Geometry::compute(512, 52, 1.0, 1.0);
  const RowRestorer accumulation(slow, ones, 1.0, 1.0);
  EXPECT_EQ(accumulation.zero_bins(), 2);
  EXPECT_EQ(accumulation.transform_length(), restoration_transform_length(slow));
}

TEST(Restore, ConstantImageIsRestoredExactly) {
  const std::vector<double> gains = raskar();
  const Image input(512, 4, 1, 80.0);
  ReferenceParams params;
  params.threads = 1;
  const Image observation = convolve_rows(row_spectra(input, 1), gains, params);
  const Geometry g = Geometry::compute(512, 52, 1.0, 1.0);
  const Restoration r = restore(observation, input, g, gains, 1.0, 1.0, 1);
  // FFT round-off on values of order K(0) * 80 = 2080.
  for (const double v : r.restored.data) ASSERT_NEAR(v, 80.0, 1e-9);
  for (const double v : r.observed.data) ASSERT_NEAR(v, 26.0 * 80.0, 1e-9);
}

// The restoration of a noise-free observation is aligned with the ground
// truth: shifting it by one column makes the error much larger.
class RestoreAlignment : public ::testing::TestWithParam<double> {};

TEST_P(RestoreAlignment, RestoredIsAlignedWithGroundTruth) {
  const double v = GetParam();
  const std::vector<double> gains = raskar();
  const Image input = test::make_test_image(512, 16, 1, 4);
  ReferenceParams params;
  params.velocity = v;
  params.threads = 2;
  const Image observation = convolve_rows(row_spectra(input, 2), gains, params);
  const Geometry g = Geometry::compute(512, 52, v, 1.0);
  const Restoration r = restore(observation, input, g, gains, v, 1.0, 2);
  const int first = g.blur_length;
  const int end = g.output_width - g.blur_length;
  auto error_at_shift = [&](int shift) {
    double sum = 0.0;
    for (int y = 0; y < r.restored.height; ++y) {
      for (int x = first; x < end; ++x) {
        const double d = r.groundtruth.at(0, y, x) - r.restored.at(0, y, x + shift);
        sum += d * d;
      }
    }
    return std::sqrt(sum / ((end - first) * r.restored.height));
  };
  const double aligned = error_at_shift(0);
  EXPECT_LT(aligned, 0.5 * error_at_shift(1)) << "v = " << v;
  EXPECT_LT(aligned, 0.5 * error_at_shift(-1)) << "v = " << v;
}

INSTANTIATE_TEST_SUITE_P(Velocities, RestoreAlignment, ::testing::Values(1.0, -1.0, 0.5));

}  // namespace
}  // namespace fss
