// Tests of fss/metrics.h: RMSE, PSNR, midway equalization, the contrast
// invariant RMSE and the residual display (SPEC 5).

#include "fss/pipeline/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <random>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"

namespace fss {
namespace {

// Image of the given size with values from a uniform distribution, rounded to
// integers when `integers` is set (many ties, like 8-bit ground truth).
Image random_image(int width, int height, int channels, unsigned seed, double lo, double hi,
                   bool integers) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> value(lo, hi);
  Image image(width, height, channels);
  for (double& v : image.data) v = integers ? std::round(value(rng)) : value(rng);
  return image;
}

std::vector<double> sorted_channel(const Image& image, int c) {
  const auto first = image.data.begin() + static_cast<std::ptrdiff_t>(c * image.plane_size());
  std::vector<double> values(first, first + static_cast<std::ptrdiff_t>(image.plane_size()));
  std::sort(values.begin(), values.end());
  return values;
}

void expect_throws_error(const std::function<void()>& call, const char* what) {
  EXPECT_THROW(call(), Error) << what;
}

TEST(Rmse, HandMadeImageExactValue) {
  // 4 x 2 gray. Differences in the window [1, 3): 1, -1, 3, -1 -> sqrt(12 / 4).
  Image a(4, 2, 1, 0.0);
  Image b(4, 2, 1, 0.0);
  b.at(0, 0, 1) = 1.0;
  b.at(0, 0, 2) = -1.0;
  b.at(0, 1, 1) = 3.0;
  b.at(0, 1, 2) = -1.0;
  // Outside the window: huge differences that must not count.
  b.at(0, 0, 0) = 1000.0;
  b.at(0, 1, 3) = -500.0;
  EXPECT_DOUBLE_EQ(rmse(a, b, 1, 3), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(rmse(b, a, 1, 3), std::sqrt(3.0));
  // Single columns.
  EXPECT_DOUBLE_EQ(rmse(a, b, 1, 2), std::sqrt(5.0));  // (1 + 9) / 2
  EXPECT_DOUBLE_EQ(rmse(a, b, 2, 3), 1.0);             // (1 + 1) / 2
  EXPECT_DOUBLE_EQ(rmse(a, b, 0, 1), std::sqrt(500000.0));
  // Whole image: (1e6 + 1 + 1 + 9 + 1 + 250000) / 8.
  EXPECT_DOUBLE_EQ(rmse(a, b, 0, 4), std::sqrt(1250012.0 / 8.0));
  EXPECT_EQ(rmse(a, a, 0, 4), 0.0);
}

TEST(Rmse, ChannelsArePooled) {
  // Constant differences 1, 2, 2 in the three channels: pooled mean square
  // (1 + 4 + 4) / 3 = 3, not the mean of the per-channel RMSEs (5/3).
  Image a(5, 3, 3, 10.0);
  Image b(5, 3, 3, 10.0);
  const double offsets[3] = {1.0, 2.0, -2.0};
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 5; ++x) b.at(c, y, x) += offsets[c];
    }
  }
  EXPECT_DOUBLE_EQ(rmse(a, b, 0, 5), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(rmse(a, b, 2, 4), std::sqrt(3.0));
}

TEST(Rmse, ThrowsOnSizeMismatch) {
  const Image a(6, 4, 1);
  expect_throws_error([&] { rmse(a, Image(5, 4, 1), 0, 5); }, "width");
  expect_throws_error([&] { rmse(a, Image(6, 3, 1), 0, 6); }, "height");
  expect_throws_error([&] { rmse(a, Image(6, 4, 3), 0, 6); }, "channels");
  expect_throws_error([&] { rmse_contrast_invariant(a, Image(5, 4, 1), 0, 5); }, "ci width");
  expect_throws_error([&] { rmse_contrast_invariant(a, Image(6, 4, 3), 0, 6); }, "ci channels");
  expect_throws_error([&] { midway_equalize(a, Image(6, 5, 1)); }, "midway");
  expect_throws_error([&] { residual_display(a, Image(7, 4, 1)); }, "residual");
}

TEST(Rmse, ThrowsOnEmptyOrOutOfRangeWindow) {
  const Image a(6, 4, 1, 1.0);
  const Image b(6, 4, 1, 2.0);
  expect_throws_error([&] { rmse(a, b, 3, 3); }, "empty");
  expect_throws_error([&] { rmse(a, b, 4, 2); }, "reversed");
  expect_throws_error([&] { rmse(a, b, -1, 3); }, "negative first");
  expect_throws_error([&] { rmse(a, b, 0, 7); }, "end past width");
  expect_throws_error([&] { rmse(a, b, 6, 7); }, "first at width");
  expect_throws_error([&] { rmse_contrast_invariant(a, b, 2, 2); }, "ci empty");
  expect_throws_error([&] { rmse_contrast_invariant(a, b, 0, 7); }, "ci end past width");
  expect_throws_error([&] { rmse_contrast_invariant(a, b, -2, 3); }, "ci negative first");
  // The full window is fine.
  EXPECT_DOUBLE_EQ(rmse(a, b, 0, 6), 1.0);
}

TEST(Rmse, ErrorsAreUsageErrors) {
  const Image a(6, 4, 1);
  try {
    rmse(a, Image(5, 4, 1), 0, 5);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kUsage);
  }
  try {
    rmse(a, a, 2, 2);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kUsage);
  }
}

TEST(Psnr, Formula) {
  // A few ulps of log10.
  EXPECT_NEAR(psnr(1.0), 20.0 * std::log10(255.0), 1e-12);
  EXPECT_NEAR(psnr(255.0), 0.0, 1e-12);
  EXPECT_NEAR(psnr(2.5), 20.0 * std::log10(255.0 / 2.5), 1e-12);
  // The reference tool's printed pair; its RMSE is rounded to 6 digits
  // (+/- 5e-7), which moves the PSNR by up to 20 / ln 10 / 0.417 * 5e-7 ~ 1e-5.
  EXPECT_NEAR(psnr(0.417289), 55.722061, 2e-5);
}

TEST(MidwayEqualize, BothOutputsShareTheSortedValues) {
  const Image a = random_image(13, 7, 1, 1, 0.0, 255.0, true);
  const Image b = random_image(13, 7, 1, 2, -20.0, 300.0, false);
  const auto [ea, eb] = midway_equalize(a, b);
  ASSERT_EQ(ea.width, 13);
  ASSERT_EQ(ea.height, 7);
  ASSERT_EQ(ea.channels, 1);
  ASSERT_EQ(eb.data.size(), b.data.size());
  const auto sa = sorted_channel(a, 0);
  const auto sb = sorted_channel(b, 0);
  std::vector<double> midway(sa.size());
  for (std::size_t i = 0; i < sa.size(); ++i) midway[i] = 0.5 * (sa[i] + sb[i]);
  EXPECT_EQ(sorted_channel(ea, 0), midway);
  EXPECT_EQ(sorted_channel(eb, 0), midway);
}

TEST(MidwayEqualize, PreservesRankOrder) {
  const Image a = random_image(11, 9, 1, 3, 0.0, 20.0, true);  // many ties
  const Image b = random_image(11, 9, 1, 4, 0.0, 255.0, false);
  const auto [ea, eb] = midway_equalize(a, b);
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    for (std::size_t j = 0; j < a.data.size(); ++j) {
      if (a.data[i] < a.data[j]) {
        ASSERT_LE(ea.data[i], ea.data[j]) << i << " " << j;
      }
      if (b.data[i] < b.data[j]) {
        ASSERT_LE(eb.data[i], eb.data[j]) << i << " " << j;
      }
    }
  }
}

TEST(MidwayEqualize, OfAnImageWithItselfIsTheImage) {
  const Image a = random_image(10, 6, 3, 5, 0.0, 255.0, true);
  const auto [ea, eb] = midway_equalize(a, a);
  // (x + x) / 2 = x exactly in floating point.
  EXPECT_EQ(ea.data, a.data);
  EXPECT_EQ(eb.data, a.data);
}

TEST(MidwayEqualize, ChannelsAreEqualizedIndependently) {
  // Channel ranges far apart: pooling channels would mix them.
  Image a(8, 5, 3);
  Image b(8, 5, 3);
  const double a_base[3] = {0.0, 1000.0, -50.0};
  const double b_base[3] = {500.0, 10.0, 7.0};
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 5; ++y) {
      for (int x = 0; x < 8; ++x) {
        a.at(c, y, x) = a_base[c] + std::round(10.0 * unit(rng));
        b.at(c, y, x) = b_base[c] + 3.0 * unit(rng);
      }
    }
  }
  const auto [ea, eb] = midway_equalize(a, b);
  for (int c = 0; c < 3; ++c) {
    const auto sa = sorted_channel(a, c);
    const auto sb = sorted_channel(b, c);
    std::vector<double> midway(sa.size());
    for (std::size_t i = 0; i < sa.size(); ++i) midway[i] = 0.5 * (sa[i] + sb[i]);
    EXPECT_EQ(sorted_channel(ea, c), midway) << "channel " << c;
    EXPECT_EQ(sorted_channel(eb, c), midway) << "channel " << c;
  }
}

TEST(MidwayEqualize, TiesAreRankedColumnMajor) {
  // a is constant (all tied); b has distinct values. The r-th pixel of a in
  // column-major order (index x * height + y) receives the r-th midway value.
  // Row-major or any other order would put different values on the pixels.
  const int width = 3;
  const int height = 2;
  Image a(width, height, 1, 5.0);
  Image b(width, height, 1);
  // b in row-major order: 10, 40, 20 / 50, 30, 60.
  const double b_values[6] = {10.0, 40.0, 20.0, 50.0, 30.0, 60.0};
  for (int i = 0; i < 6; ++i) b.data[i] = b_values[i];
  const auto [ea, eb] = midway_equalize(a, b);
  const double sorted_b[6] = {10.0, 20.0, 30.0, 40.0, 50.0, 60.0};
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) {
      const int rank = x * height + y;
      EXPECT_EQ(ea.at(0, y, x), 0.5 * (5.0 + sorted_b[rank])) << "x " << x << " y " << y;
    }
  }
  // b has no ties: each of its pixels gets the midway value of its own rank.
  for (int i = 0; i < 6; ++i) {
    const int rank = static_cast<int>(std::find(sorted_b, sorted_b + 6, b_values[i]) - sorted_b);
    EXPECT_EQ(eb.data[i], 0.5 * (5.0 + sorted_b[rank])) << "pixel " << i;
  }
  // Spelled out: column 0 gets ranks 0, 1; column 1 ranks 2, 3; column 2 ranks 4, 5.
  EXPECT_EQ(ea.at(0, 0, 0), 7.5);
  EXPECT_EQ(ea.at(0, 1, 0), 12.5);
  EXPECT_EQ(ea.at(0, 0, 1), 17.5);
  EXPECT_EQ(ea.at(0, 1, 1), 22.5);
  EXPECT_EQ(ea.at(0, 0, 2), 27.5);
  EXPECT_EQ(ea.at(0, 1, 2), 32.5);
}

TEST(MidwayEqualize, PartialTiesAreRankedColumnMajorWithinTheirValue) {
  // a: two tied groups (1 and 2); within each group column-major order decides.
  // Row-major a = 2 1 2 / 1 2 1 (width 3, height 2).
  const int width = 3;
  const int height = 2;
  Image a(width, height, 1);
  const double a_values[6] = {2.0, 1.0, 2.0, 1.0, 2.0, 1.0};
  for (int i = 0; i < 6; ++i) a.data[i] = a_values[i];
  Image b(width, height, 1);
  for (int i = 0; i < 6; ++i) b.data[i] = 100.0 * (i + 1);  // sorted: 100 .. 600
  const auto [ea, eb] = midway_equalize(a, b);
  // Value 1 pixels in column-major order: (x0,y1), (x1,y0), (x2,y1) -> ranks 0, 1, 2.
  // Value 2 pixels: (x0,y0), (x1,y1), (x2,y0) -> ranks 3, 4, 5.
  EXPECT_EQ(ea.at(0, 1, 0), 0.5 * (1.0 + 100.0));
  EXPECT_EQ(ea.at(0, 0, 1), 0.5 * (1.0 + 200.0));
  EXPECT_EQ(ea.at(0, 1, 2), 0.5 * (1.0 + 300.0));
  EXPECT_EQ(ea.at(0, 0, 0), 0.5 * (2.0 + 400.0));
  EXPECT_EQ(ea.at(0, 1, 1), 0.5 * (2.0 + 500.0));
  EXPECT_EQ(ea.at(0, 0, 2), 0.5 * (2.0 + 600.0));
}

TEST(RmseContrastInvariant, ZeroForAStrictlyIncreasingMap) {
  const Image a = random_image(20, 9, 1, 7, 1.0, 30.0, true);  // positive, many ties
  Image affine = a;
  Image square = a;
  Image cube_root = a;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    affine.data[i] = 2.0 * a.data[i] + 3.0;
    square.data[i] = a.data[i] * a.data[i];
    cube_root.data[i] = std::cbrt(a.data[i]) - 100.0;
  }
  // Same ranks (ties broken by the same index) give the same midway image.
  EXPECT_EQ(rmse_contrast_invariant(a, affine, 0, 20), 0.0);
  EXPECT_EQ(rmse_contrast_invariant(a, square, 0, 20), 0.0);
  EXPECT_EQ(rmse_contrast_invariant(square, cube_root, 3, 17), 0.0);
  EXPECT_EQ(rmse_contrast_invariant(a, a, 0, 20), 0.0);
  // Plain RMSE is not zero, so the check above is not vacuous.
  EXPECT_GT(rmse(a, square, 0, 20), 1.0);
}

TEST(RmseContrastInvariant, ZeroPerChannelWithDifferentMaps) {
  const Image a = random_image(12, 6, 3, 8, 0.0, 255.0, true);
  Image b = a;
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 6; ++y) {
      for (int x = 0; x < 12; ++x) {
        const double v = a.at(c, y, x);
        b.at(c, y, x) = c == 0 ? 0.5 * v : (c == 1 ? v + 1000.0 : std::exp(v / 50.0));
      }
    }
  }
  EXPECT_EQ(rmse_contrast_invariant(a, b, 0, 12), 0.0);
}

// Sorting a and b at the same time (more than one thread, a window of at
// most kParallelSortPixels) gives the bits of sorting them one after the
// other.
TEST(RmseContrastInvariant, ThreadsDoNotChangeTheResult) {
  const Image a = random_image(300, 200, 3, 31, 0.0, 255.0, true);
  const Image b = random_image(300, 200, 3, 32, -30.0, 290.0, false);
  const double one = rmse_contrast_invariant(a, b, 10, 290, 1);
  EXPECT_GT(one, 0.0);
  EXPECT_EQ(rmse_contrast_invariant(a, b, 10, 290, 2), one);
  EXPECT_EQ(rmse_contrast_invariant(a, b, 10, 290, 0), one);
  EXPECT_EQ(rmse_contrast_invariant(a, 5, crop_columns(b, 5, 290), 5, 285, 2),
            rmse_contrast_invariant(a, 5, crop_columns(b, 5, 290), 5, 285, 1));
}

TEST(RmseContrastInvariant, IsTheRmseOfTheEqualizedWindow) {
  const Image a = random_image(16, 8, 1, 9, 0.0, 255.0, true);
  const Image b = random_image(16, 8, 1, 10, 0.0, 255.0, false);
  const auto [ea, eb] = midway_equalize(crop_columns(a, 4, 9), crop_columns(b, 4, 9));
  // Same arithmetic on the same values.
  EXPECT_DOUBLE_EQ(rmse_contrast_invariant(a, b, 4, 13), rmse(ea, eb, 0, 9));
  // Columns outside the window do not matter.
  Image a2 = a;
  for (int y = 0; y < 8; ++y) {
    a2.at(0, y, 0) = 1e6;
    a2.at(0, y, 15) = -1e6;
  }
  EXPECT_EQ(rmse_contrast_invariant(a2, b, 4, 13), rmse_contrast_invariant(a, b, 4, 13));
  EXPECT_GT(rmse_contrast_invariant(a, b, 4, 13), 0.0);
}

// midway_equalize by a comparison sort of (value, column-major index), with
// the documented resolution of values: the order-preserving bits of a value
// without their low bit_width(n - 1) bits (values closer than about
// 2^(bits - 52) relative tie, ranked by index as equal values are).
std::pair<Image, Image> midway_by_comparison(const Image& a, const Image& b) {
  Image ea(a.width, a.height, a.channels);
  Image eb(b.width, b.height, b.channels);
  const auto h = static_cast<std::size_t>(a.height);
  const std::size_t n = a.plane_size();
  const int index_bits = std::max(1, static_cast<int>(std::bit_width(n - 1)));
  const std::uint64_t resolution = ~((std::uint64_t{1} << index_bits) - 1);
  auto ordered_bits = [&](double v) {
    if (v == 0.0) v = 0.0;  // -0 and +0 are equal values
    const auto bits = std::bit_cast<std::uint64_t>(v);
    return ((bits >> 63) ? ~bits : bits | (std::uint64_t{1} << 63)) & resolution;
  };
  for (int c = 0; c < a.channels; ++c) {
    auto value = [&](const Image& image, std::size_t i) {
      return image.at(c, static_cast<int>(i % h), static_cast<int>(i / h));
    };
    auto ranked = [&](const Image& image) {
      std::vector<std::size_t> order(n);
      for (std::size_t i = 0; i < n; ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
        const std::uint64_t vi = ordered_bits(value(image, i)), vj = ordered_bits(value(image, j));
        return vi < vj || (vi == vj && i < j);
      });
      return order;
    };
    const std::vector<std::size_t> ra = ranked(a), rb = ranked(b);
    for (std::size_t r = 0; r < n; ++r) {
      const double mid = 0.5 * (value(a, ra[r]) + value(b, rb[r]));
      ea.at(c, static_cast<int>(ra[r] % h), static_cast<int>(ra[r] / h)) = mid;
      eb.at(c, static_cast<int>(rb[r] % h), static_cast<int>(rb[r] / h)) = mid;
    }
  }
  return {std::move(ea), std::move(eb)};
}

// Sizes and value mixes for the radix sorter's short runs and buffered
// least-significant-digit passes: keys differing in the sign bit (negatives,
// -0 and +0), huge and tiny magnitudes, integer ties.
TEST(MidwayEqualize, MatchesAComparisonSortOnShortAndBufferedRuns) {
  for (const auto& [width, height] : {std::pair{7, 5}, {40, 30}, {310, 211}, {1200, 100}}) {
    Image a = random_image(width, height, 2, 21, -5.0, 260.0, true);
    Image b = random_image(width, height, 2, 22, -40.0, 300.0, false);
    std::mt19937_64 rng(23);
    for (std::size_t i = 0; i < b.data.size(); i += 17) {
      switch (rng() % 5) {
        case 0:
          b.data[i] = -0.0;
          break;
        case 1:
          b.data[i] = 0.0;
          break;
        case 2:
          b.data[i] = 1e150 * static_cast<double>(rng() % 7);
          break;
        case 3:
          b.data[i] = -1e-300 * static_cast<double>(rng() % 7);
          break;
        default:
          b.data[i] = std::round(b.data[i]);
          break;
      }
    }
    const auto [ea, eb] = midway_equalize(a, b);
    const auto [ra, rb] = midway_by_comparison(a, b);
    EXPECT_EQ(ea.data, ra.data) << width << "x" << height;
    EXPECT_EQ(eb.data, rb.data) << width << "x" << height;
    // The same ranks in the contrast-invariant RMSE (summed in another order).
    const Image a1 = crop_columns(a, 0, width), b1 = crop_columns(b, 0, width);
    const double expected = rmse(ra, rb, 0, width);
    EXPECT_NEAR(rmse_contrast_invariant(a1, b1, 0, width), expected, 1e-12 * expected);
  }
}

// A window longer than the sorter's buffer (256 Ki keys) is split in place;
// values sharing their sign and exponent (here [128, 256), a few negatives
// making the sign bit differ) put most keys in one part, which is split
// again before the buffered passes.
TEST(MidwayEqualize, MatchesAComparisonSortWhenSplittingInPlace) {
  const Image a = random_image(700, 500, 1, 41, 0.0, 255.0, true);
  Image b = random_image(700, 500, 1, 42, 128.0, 256.0, false);
  for (std::size_t i = 0; i < b.data.size(); i += 997) b.data[i] = -b.data[i];
  for (std::size_t i = 5; i < b.data.size(); i += 1999) b.data[i] = std::round(b.data[i]);
  const auto [ea, eb] = midway_equalize(a, b);
  const auto [ra, rb] = midway_by_comparison(a, b);
  EXPECT_EQ(ea.data, ra.data);
  EXPECT_EQ(eb.data, rb.data);
}

double min_of(const Image& image) {
  return *std::min_element(image.data.begin(), image.data.end());
}
double max_of(const Image& image) {
  return *std::max_element(image.data.begin(), image.data.end());
}

TEST(ResidualDisplay, FirstPixelHoldsTheMaximum) {
  Image a(4, 3, 1, 10.0);
  Image b(4, 3, 1, 0.0);
  a.data[0] = 90.0;  // a - b is maximal at the very first pixel
  a.data[7] = -5.0;  // and minimal here
  const Image d = residual_display(a, b);
  EXPECT_EQ(d.data[0], 255.0);
  EXPECT_EQ(d.data[7], 0.0);
  EXPECT_EQ(min_of(d), 0.0);
  EXPECT_EQ(max_of(d), 255.0);
  // Affine: (10 - (-5)) / (90 - (-5)) * 255 elsewhere; a few ulps.
  EXPECT_NEAR(d.data[5], 15.0 / 95.0 * 255.0, 1e-12);
}

TEST(ResidualDisplay, FirstPixelHoldsTheMinimum) {
  Image a(4, 3, 1, 10.0);
  Image b(4, 3, 1, 3.0);
  b.data[0] = 50.0;    // a - b = -40 at the first pixel, the minimum
  b.data[11] = -20.0;  // a - b = 30, the maximum, at the last pixel
  const Image d = residual_display(a, b);
  EXPECT_EQ(d.data[0], 0.0);
  EXPECT_EQ(d.data[11], 255.0);
  EXPECT_EQ(min_of(d), 0.0);
  EXPECT_EQ(max_of(d), 255.0);
  EXPECT_NEAR(d.data[4], 47.0 / 70.0 * 255.0, 1e-12);  // a few ulps
}

double range_of_difference(const Image& a, const Image& b) {
  double lo = a.data[0] - b.data[0];
  double hi = lo;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    lo = std::min(lo, a.data[i] - b.data[i]);
    hi = std::max(hi, a.data[i] - b.data[i]);
  }
  return hi - lo;
}

TEST(ResidualDisplay, ExtremesAreExactForAwkwardRanges) {
  // The maximum must map to 255 exactly, whatever the range (d - min) * 255 /
  // (max - min) rounds to: e.g. x * (255 / x) is not always 255 in doubles.
  // Simple ranges where (hi - lo) * (255 / (hi - lo)) is not 255 in doubles.
  for (const double range : {11.0, 13.0, 100.0, 0.7}) {
    Image a(2, 1, 1, 0.0);
    a.data[1] = range;
    const Image d = residual_display(a, Image(2, 1, 1, 0.0));
    EXPECT_EQ(d.data[0], 0.0) << "range " << range;
    EXPECT_EQ(d.data[1], 255.0) << std::setprecision(17) << "range " << range << ": got "
                                << d.data[1];
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> value(-300.0, 300.0);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Image a(5, 2, 1);
    Image b(5, 2, 1);
    for (double& v : a.data) v = value(rng);
    for (double& v : b.data) v = value(rng);
    const Image d = residual_display(a, b);
    ASSERT_EQ(min_of(d), 0.0) << "trial " << trial;
    ASSERT_EQ(max_of(d), 255.0) << std::setprecision(17) << "trial " << trial << ": max "
                                << max_of(d) << ", range of a - b " << range_of_difference(a, b);
    ++checked;
  }
  EXPECT_EQ(checked, 200);
}

TEST(ResidualDisplay, ChannelsMappedJointly) {
  // Channel 0 spans a - b in [0, 100], channel 1 in [40, 60]: only the joint
  // extremes reach 0 and 255.
  Image a(3, 2, 2, 0.0);
  const Image b(3, 2, 2, 0.0);
  const double c0[6] = {0.0, 100.0, 50.0, 25.0, 75.0, 10.0};
  const double c1[6] = {40.0, 60.0, 50.0, 45.0, 55.0, 42.0};
  for (int i = 0; i < 6; ++i) {
    a.data[i] = c0[i];
    a.data[6 + i] = c1[i];
  }
  const Image d = residual_display(a, b);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(d.data[i], c0[i] * 2.55, 1e-12) << i;          // a few ulps
    EXPECT_NEAR(d.data[6 + i], c1[i] * 2.55, 1e-12) << 6 + i;  // a few ulps
  }
  // Exactness of the extremes is ExtremesAreExactForAwkwardRanges' business.
  EXPECT_EQ(d.data[0], 0.0);
  EXPECT_NEAR(d.data[1], 255.0, 1e-12);
}

TEST(ResidualDisplay, ConstantDifferenceGivesZero) {
  const Image a = random_image(6, 4, 3, 12, 0.0, 255.0, false);
  const Image exact_a(6, 4, 3, 200.0);
  const Image exact_b(6, 4, 3, 150.0);
  const Image d = residual_display(exact_a, exact_b);
  ASSERT_EQ(d.width, 6);
  ASSERT_EQ(d.height, 4);
  ASSERT_EQ(d.channels, 3);
  for (const double v : d.data) EXPECT_EQ(v, 0.0);
  const Image same = residual_display(a, a);
  for (const double v : same.data) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace fss
