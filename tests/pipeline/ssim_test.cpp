// Tests of src/pipeline/ssim.h: the structural similarity over the RMSE window against a direct
// 2-D computation, its known properties, its windows and errors, and its independence of the
// thread count.

#include "pipeline/ssim.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "support/test_util.h"

namespace fss {
namespace {

constexpr int kR = 5;

Image random_image(int width, int height, int channels, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> value(0.0, 255.0);
  Image image(width, height, channels);
  for (double& v : image.data) v = value(rng);
  return image;
}

// The restoration as a noisy copy of columns [offset, offset + width) of the input.
Image noisy_crop(const Image& input, int offset, int width, double noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  Image out(width, input.height, input.channels);
  for (int c = 0; c < input.channels; ++c) {
    for (int y = 0; y < input.height; ++y) {
      for (int x = 0; x < width; ++x) out.at(c, y, x) = input.at(c, y, x + offset) + normal(rng);
    }
  }
  return out;
}

// The 11 x 11 weights exp(-(i^2 + j^2) / (2 sigma^2)) normalised to sum 1, indexed [i + r][j + r].
std::vector<std::vector<double>> weights_2d() {
  std::vector<std::vector<double>> w(2 * kR + 1, std::vector<double>(2 * kR + 1));
  double sum = 0.0;
  for (int i = -kR; i <= kR; ++i) {
    for (int j = -kR; j <= kR; ++j) {
      w[i + kR][j + kR] = std::exp(-(i * i + j * j) / (2.0 * 1.5 * 1.5));
      sum += w[i + kR][j + kR];
    }
  }
  for (auto& row : w) {
    for (double& v : row) v /= sum;
  }
  return w;
}

// SSIM by its definition, each pixel by a double loop over its 11 x 11 neighbours.
double direct_ssim(const Image& input, int offset, const Image& restored, int first, int end) {
  const auto w = weights_2d();
  const double c1 = std::pow(0.01 * 255.0, 2.0);
  const double c2 = std::pow(0.03 * 255.0, 2.0);
  double total = 0.0;
  for (int c = 0; c < restored.channels; ++c) {
    double sum = 0.0;
    for (int y = kR; y < restored.height - kR; ++y) {
      for (int x = first; x < end; ++x) {
        double mg = 0.0, mx = 0.0, egg = 0.0, exx = 0.0, egx = 0.0;
        for (int i = -kR; i <= kR; ++i) {
          for (int j = -kR; j <= kR; ++j) {
            const double g = input.at(c, y + i, x + j + offset);
            const double v = restored.at(c, y + i, x + j);
            const double weight = w[i + kR][j + kR];
            mg += weight * g;
            mx += weight * v;
            egg += weight * g * g;
            exx += weight * v * v;
            egx += weight * g * v;
          }
        }
        const double var_g = egg - mg * mg;
        const double var_x = exx - mx * mx;
        const double cov = egx - mg * mx;
        sum += (2.0 * mg * mx + c1) * (2.0 * cov + c2) /
               ((mg * mg + mx * mx + c1) * (var_g + var_x + c2));
      }
    }
    total += sum / (static_cast<double>(end - first) * (restored.height - 2 * kR));
  }
  return total / restored.channels;
}

double ssim_value(const Image& input, int offset, const Image& restored, int first, int end,
                  int threads = 1) {
  const std::optional<double> value =
      structural_similarity(input, offset, restored, first, end, threads);
  EXPECT_TRUE(value.has_value());
  return value.value_or(NAN);
}

struct Case {
  int width, height, channels, offset, first, end;
  double noise;
};

TEST(StructuralSimilarity, MatchesTheDirectComputation) {
  // Sizes across the 512-column tiles and the 32-row blocks, windows at the edges and inside,
  // with the input wider than the restoration.
  const Case cases[] = {
      {11, 11, 1, 0, 5, 6, 10.0},     {23, 17, 1, 3, 5, 18, 30.0},  {40, 45, 3, 0, 7, 30, 5.0},
      {530, 12, 2, 4, 5, 525, 20.0},  {60, 70, 1, 1, 20, 55, 80.0}, {35, 33, 4, 2, 5, 30, 0.5},
      {600, 11, 1, 0, 500, 595, 3.0},
  };
  std::uint64_t seed = 1;
  for (const Case& k : cases) {
    SCOPED_TRACE(::testing::Message() << k.width << "x" << k.height << "x" << k.channels
                                      << " window [" << k.first << ", " << k.end << ")");
    const Image input = random_image(k.width + 2 * k.offset, k.height, k.channels, seed++);
    const Image restored = noisy_crop(input, k.offset, k.width, k.noise, seed++);
    EXPECT_NEAR(ssim_value(input, k.offset, restored, k.first, k.end),
                direct_ssim(input, k.offset, restored, k.first, k.end), 1e-12);
    // Two independent random images: SSIM near 0.
    const Image other = random_image(k.width, k.height, k.channels, seed++);
    EXPECT_NEAR(ssim_value(input, k.offset, other, k.first, k.end),
                direct_ssim(input, k.offset, other, k.first, k.end), 1e-12);
  }
}

TEST(StructuralSimilarity, MatchesTheDirectComputationOnSmoothBrightImages) {
  // Small local variances under large means: the cancellation in E[g^2] - mu_g^2.
  const Image input = test::make_test_image(70, 40, 3, 7);
  Image bright = input;
  for (double& v : bright.data) v = 200.0 + v / 5.0;
  const Image restored = noisy_crop(bright, 0, 70, 1.0, 8);
  EXPECT_NEAR(ssim_value(bright, 0, restored, 5, 65), direct_ssim(bright, 0, restored, 5, 65),
              1e-12);
}

TEST(StructuralSimilarity, IdenticalImagesGiveExactlyOne) {
  const Image input = random_image(50, 30, 3, 11);
  EXPECT_EQ(ssim_value(input, 0, input, 5, 45), 1.0);
  const Image crop = crop_columns(input, 6, 30);
  EXPECT_EQ(ssim_value(input, 6, crop, 5, 25), 1.0);
  const Image flat(20, 20, 1, 128.0);
  EXPECT_EQ(ssim_value(flat, 0, flat, 5, 15), 1.0);
}

// The variances are taken about the ground truth's mean: at a level of 1e10 or 1e15 they keep
// their precision (E[g^2] - mu^2 about 0 would lose every digit).
TEST(StructuralSimilarity, KeepsItsPrecisionAtAnyLevel) {
  const Image flat(20, 20, 1, 1e15);
  EXPECT_EQ(ssim_value(flat, 0, flat, 5, 15), 1.0);
  const Image input = random_image(60, 30, 1, 21);
  const Image restored = noisy_crop(input, 0, 60, 5.0, 22);
  const auto lifted = [](Image image, double level) {
    for (double& v : image.data) v += level;
    return image;
  };
  // Far above the data's spread the luminance term is 1 to 1e-18: SSIM is the structure term,
  // the same at every such level.
  const double at_1e6 = ssim_value(lifted(input, 1e6), 0, lifted(restored, 1e6), 5, 55);
  for (const double level : {1e8, 1e10, 1e12}) {
    const double value = ssim_value(lifted(input, level), 0, lifted(restored, level), 5, 55);
    EXPECT_GE(value, -1.0);
    EXPECT_LE(value, 1.0);
    EXPECT_NEAR(value, at_1e6, 1e-6) << level;
  }
}

TEST(StructuralSimilarity, IsSymmetric) {
  const Image g = random_image(45, 25, 2, 21);
  const Image x = noisy_crop(g, 0, 45, 25.0, 22);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(ssim_value(g, 0, x, 5, 40)),
            std::bit_cast<std::uint64_t>(ssim_value(x, 0, g, 5, 40)));
}

TEST(StructuralSimilarity, OffsetAndContrastChangesLowerIt) {
  const Image g = test::make_test_image(60, 40, 1, 3);
  Image brighter = g;
  for (double& v : brighter.data) v += 30.0;
  Image flatter = g;
  for (double& v : flatter.data) v = 128.0 + 0.5 * (v - 128.0);
  const double brighter_ssim = ssim_value(g, 0, brighter, 5, 55);
  const double flatter_ssim = ssim_value(g, 0, flatter, 5, 55);
  EXPECT_LT(brighter_ssim, 1.0);
  EXPECT_GT(brighter_ssim, 0.5);
  EXPECT_LT(flatter_ssim, 1.0);
  EXPECT_GT(flatter_ssim, 0.5);
  // More noise, less similarity; never above 1 nor below -1.
  double previous = 1.0;
  for (double noise : {2.0, 10.0, 40.0}) {
    const double value = ssim_value(g, 0, noisy_crop(g, 0, 60, noise, 4), 5, 55);
    EXPECT_LT(value, previous);
    EXPECT_GT(value, -1.0);
    previous = value;
  }
}

TEST(StructuralSimilarity, NoPixelLeftGivesNullopt) {
  const Image tall = random_image(30, 11, 1, 31);
  EXPECT_TRUE(structural_similarity(tall, 0, tall, 5, 25).has_value());
  const Image short_image = random_image(30, 10, 1, 32);
  EXPECT_FALSE(structural_similarity(short_image, 0, short_image, 5, 25).has_value());
  EXPECT_FALSE(structural_similarity(tall, 0, tall, 4, 25).has_value());
  EXPECT_FALSE(structural_similarity(tall, 0, tall, 0, 25).has_value());
  EXPECT_FALSE(structural_similarity(tall, 0, tall, 5, 26).has_value());
  EXPECT_FALSE(structural_similarity(tall, 0, tall, 10, 30).has_value());
  const Image none(30, 20, 0);
  EXPECT_FALSE(structural_similarity(none, 0, none, 5, 25).has_value());
}

TEST(StructuralSimilarity, ThrowsOnMismatchedImagesOrWindows) {
  const Image input = random_image(40, 20, 3, 41);
  const Image restored = random_image(30, 20, 3, 42);
  const auto usage = [&](const Image& a, int offset, const Image& b, int first, int end) {
    return test::throws_error([&] { structural_similarity(a, offset, b, first, end); },
                              ErrorKind::kUsage);
  };
  EXPECT_NO_THROW(structural_similarity(input, 10, restored, 5, 25));
  EXPECT_TRUE(usage(input, 11, restored, 5, 25));
  EXPECT_TRUE(usage(input, -1, restored, 5, 25));
  EXPECT_TRUE(usage(random_image(40, 21, 3, 43), 0, restored, 5, 25));
  EXPECT_TRUE(usage(random_image(40, 20, 1, 44), 0, restored, 5, 25));
  EXPECT_TRUE(usage(input, 0, restored, -1, 25));
  EXPECT_TRUE(usage(input, 0, restored, 5, 31));
  EXPECT_TRUE(usage(input, 0, restored, 12, 12));
  EXPECT_TRUE(usage(input, 0, restored, 12, 8));
}

TEST(StructuralSimilarity, ThreadCountNeverChangesTheBits) {
  // 3 channels x 7 row blocks x 3 column tiles of work items.
  const Image input = random_image(1100, 200, 3, 51);
  const Image restored = noisy_crop(input, 0, 1100, 15.0, 52);
  const std::uint64_t one = std::bit_cast<std::uint64_t>(ssim_value(input, 0, restored, 5, 1095));
  for (int threads : {2, 3, 4, 7, 64, 0}) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(ssim_value(input, 0, restored, 5, 1095, threads)), one)
        << threads << " threads";
  }
}

}  // namespace
}  // namespace fss
