// Tests of fss/pipeline/metrics.h: RMSE, PSNR, midway equalization, the
// contrast invariant RMSE and the residual display (docs/method.md §5).

#include "fss/pipeline/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"
#include "pipeline/rmse_ci_corpus.h"
#include "support/test_util.h"

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
  EXPECT_TRUE(test::throws_error([&] { rmse(a, Image(5, 4, 1), 0, 5); }, ErrorKind::kUsage,
                                 {"different sizes"}))
      << "width";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, Image(6, 3, 1), 0, 6); }, ErrorKind::kUsage,
                                 {"different sizes"}))
      << "height";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, Image(6, 4, 3), 0, 6); }, ErrorKind::kUsage,
                                 {"different sizes"}))
      << "channels";
  EXPECT_TRUE(test::throws_error([&] { rmse_contrast_invariant(a, Image(5, 4, 1), 0, 5); },
                                 ErrorKind::kUsage, {"different sizes"}))
      << "ci width";
  EXPECT_TRUE(test::throws_error([&] { rmse_contrast_invariant(a, Image(6, 4, 3), 0, 6); },
                                 ErrorKind::kUsage, {"different sizes"}))
      << "ci channels";
  EXPECT_TRUE(test::throws_error([&] { midway_equalize(a, Image(6, 5, 1)); }, ErrorKind::kUsage,
                                 {"different sizes"}))
      << "midway";
  EXPECT_TRUE(test::throws_error([&] { residual_display(a, Image(7, 4, 1)); }, ErrorKind::kUsage,
                                 {"different sizes"}))
      << "residual";
}

TEST(Rmse, ThrowsOnEmptyOrOutOfRangeWindow) {
  const Image a(6, 4, 1, 1.0);
  const Image b(6, 4, 1, 2.0);
  EXPECT_TRUE(test::throws_error([&] { rmse(a, b, 3, 3); }, ErrorKind::kUsage, {"column window"}))
      << "empty";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, b, 4, 2); }, ErrorKind::kUsage, {"column window"}))
      << "reversed";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, b, -1, 3); }, ErrorKind::kUsage, {"column window"}))
      << "negative first";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, b, 0, 7); }, ErrorKind::kUsage, {"column window"}))
      << "end past width";
  EXPECT_TRUE(test::throws_error([&] { rmse(a, b, 6, 7); }, ErrorKind::kUsage, {"column window"}))
      << "first at width";
  EXPECT_TRUE(test::throws_error([&] { rmse_contrast_invariant(a, b, 2, 2); }, ErrorKind::kUsage,
                                 {"column window"}))
      << "ci empty";
  EXPECT_TRUE(test::throws_error([&] { rmse_contrast_invariant(a, b, 0, 7); }, ErrorKind::kUsage,
                                 {"column window"}))
      << "ci end past width";
  EXPECT_TRUE(test::throws_error([&] { rmse_contrast_invariant(a, b, -2, 3); }, ErrorKind::kUsage,
                                 {"column window"}))
      << "ci negative first";
  // The full window is fine.
  EXPECT_DOUBLE_EQ(rmse(a, b, 0, 6), 1.0);
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

// RMSE^2 under- or overflowing made the PSNR infinite (or 0 * log): it is
// finite for every RMSE but 0, whose PSNR is +inf (a perfect restoration).
TEST(Psnr, FiniteForEveryPositiveRmse) {
  EXPECT_NEAR(psnr(1e-200), 20.0 * (std::log10(255.0) + 200.0), 1e-9);
  EXPECT_NEAR(psnr(5e-324), 20.0 * (std::log10(255.0) - std::log10(5e-324)), 1e-9);
  EXPECT_NEAR(psnr(1e200), 20.0 * (std::log10(255.0) - 200.0), 1e-9);
  EXPECT_TRUE(std::isinf(psnr(0.0)) && psnr(0.0) > 0.0);
}

// Midway values of one channel: mid_i = (a_(i) + b_(i)) / 2.
std::vector<double> midway_values(const Image& a, const Image& b, int c) {
  const auto sa = sorted_channel(a, c);
  const auto sb = sorted_channel(b, c);
  std::vector<double> mid(sa.size());
  for (std::size_t i = 0; i < sa.size(); ++i) mid[i] = 0.5 * (sa[i] + sb[i]);
  return mid;
}

// The ranks [first, second) the value v holds in the sorted sample s.
std::pair<std::size_t, std::size_t> ranks_of(const std::vector<double>& s, double v) {
  const auto [lo, hi] = std::equal_range(s.begin(), s.end(), v);
  return {static_cast<std::size_t>(lo - s.begin()), static_cast<std::size_t>(hi - s.begin())};
}

// The closed form of docs/method.md §5 written the plain way, in long
// double: sum over pixels of A_G - 2 B_G B_H + A_H, B and A the means of mid
// and mid^2 over each group's ranks (from prefix sums); sqrt(sum / count),
// channels pooled.
double closed_form_rmse_ci(const Image& a, const Image& b) {
  long double total = 0.0L;
  for (int c = 0; c < a.channels; ++c) {
    const auto sa = sorted_channel(a, c);
    const auto sb = sorted_channel(b, c);
    const auto mid = midway_values(a, b, c);
    std::vector<long double> s1(mid.size() + 1, 0.0L), s2(mid.size() + 1, 0.0L);
    for (std::size_t i = 0; i < mid.size(); ++i) {
      s1[i + 1] = s1[i] + mid[i];
      s2[i + 1] = s2[i] + static_cast<long double>(mid[i]) * mid[i];
    }
    auto means = [&](std::pair<std::size_t, std::size_t> r) {
      const auto size = static_cast<long double>(r.second - r.first);
      return std::pair{(s1[r.second] - s1[r.first]) / size, (s2[r.second] - s2[r.first]) / size};
    };
    for (std::size_t p = 0; p < a.plane_size(); ++p) {
      const auto [bg, ag] = means(ranks_of(sa, a.data[c * a.plane_size() + p]));
      const auto [bh, ah] = means(ranks_of(sb, b.data[c * b.plane_size() + p]));
      total += ag - 2.0L * bg * bh + ah;
    }
  }
  return static_cast<double>(std::sqrt(total / static_cast<long double>(a.data.size())));
}

// Plain midway equalization with every tie broken by `order` (a rank among
// equal values): the squared error sum of one explicit order of the groups.
double squared_error_for_order(const Image& a, const Image& b, const std::vector<double>& a_order,
                               const std::vector<double>& b_order) {
  double sum = 0.0;
  const std::size_t n = a.plane_size();
  for (int c = 0; c < a.channels; ++c) {
    const auto mid = midway_values(a, b, c);
    auto ranks = [&](const Image& image, const std::vector<double>& order) {
      std::vector<std::size_t> pixels(n);
      for (std::size_t p = 0; p < n; ++p) pixels[p] = p;
      const double* v = image.data.data() + c * n;
      const double* o = order.data() + c * n;
      std::sort(pixels.begin(), pixels.end(), [&](std::size_t i, std::size_t j) {
        return v[i] < v[j] || (v[i] == v[j] && o[i] < o[j]);
      });
      std::vector<std::size_t> rank(n);
      for (std::size_t r = 0; r < n; ++r) rank[pixels[r]] = r;
      return rank;
    };
    const auto ra = ranks(a, a_order);
    const auto rb = ranks(b, b_order);
    for (std::size_t p = 0; p < n; ++p) {
      const double d = mid[ra[p]] - mid[rb[p]];
      sum += d * d;
    }
  }
  return sum;
}

Image reverse_columns(const Image& image) {
  Image out(image.width, image.height, image.channels);
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) out.at(c, y, x) = image.at(c, y, image.width - 1 - x);
    }
  }
  return out;
}

TEST(MidwayEqualize, WithoutTiesBothOutputsShareTheMidwayValues) {
  const Image a = random_image(13, 7, 1, 1, 0.0, 255.0, false);
  const Image b = random_image(13, 7, 1, 2, -20.0, 300.0, false);
  const auto [ea, eb] = midway_equalize(a, b);
  ASSERT_EQ(ea.width, 13);
  ASSERT_EQ(ea.height, 7);
  ASSERT_EQ(ea.channels, 1);
  ASSERT_EQ(eb.data.size(), b.data.size());
  EXPECT_EQ(sorted_channel(ea, 0), midway_values(a, b, 0));
  EXPECT_EQ(sorted_channel(eb, 0), midway_values(a, b, 0));
}

// Each pixel gets the mean of mid over the ranks of its group of equal values.
TEST(MidwayEqualize, EqualValuesGetTheMeanOfTheirGroupsMidwayValues) {
  const Image a = random_image(11, 9, 2, 3, 0.0, 12.0, true);  // many ties
  const Image b = random_image(11, 9, 2, 4, 0.0, 30.0, true);
  const auto [ea, eb] = midway_equalize(a, b);
  for (int c = 0; c < 2; ++c) {
    const auto mid = midway_values(a, b, c);
    for (const auto& [image, equalized] : {std::pair{&a, &ea}, std::pair{&b, &eb}}) {
      const auto s = sorted_channel(*image, c);
      for (std::size_t p = 0; p < image->plane_size(); ++p) {
        const std::size_t q = c * image->plane_size() + p;
        const auto [first, last] = ranks_of(s, image->data[q]);
        double sum = 0.0;
        for (std::size_t i = first; i < last; ++i) sum += mid[i];
        EXPECT_NEAR(equalized->data[q], sum / static_cast<double>(last - first), 1e-12)
            << "channel " << c << " pixel " << p;
      }
    }
  }
}

TEST(MidwayEqualize, PreservesRankOrder) {
  const Image a = random_image(11, 9, 1, 3, 0.0, 20.0, true);  // many ties
  const Image b = random_image(11, 9, 1, 4, 0.0, 255.0, false);
  const auto [ea, eb] = midway_equalize(a, b);
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    for (std::size_t j = 0; j < a.data.size(); ++j) {
      if (a.data[i] < a.data[j]) {
        ASSERT_LT(ea.data[i], ea.data[j]) << i << " " << j;
      }
      if (a.data[i] == a.data[j]) {
        ASSERT_EQ(ea.data[i], ea.data[j]) << i << " " << j;
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
  // (x + x) / 2 = x, and a group's mean of equal integers is exact.
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
        a.at(c, y, x) = a_base[c] + 10.0 * unit(rng);
        b.at(c, y, x) = b_base[c] + 3.0 * unit(rng);
      }
    }
  }
  const auto [ea, eb] = midway_equalize(a, b);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(sorted_channel(ea, c), midway_values(a, b, c)) << "channel " << c;
    EXPECT_EQ(sorted_channel(eb, c), midway_values(a, b, c)) << "channel " << c;
  }
}

TEST(MidwayEqualize, DoesNotDependOnThePixelOrder) {
  const Image a = random_image(9, 4, 1, 7, 0.0, 6.0, true);
  const Image b = random_image(9, 4, 1, 8, 0.0, 9.0, true);
  const auto [ea, eb] = midway_equalize(a, b);
  const auto [ma, mb] = midway_equalize(reverse_columns(a), reverse_columns(b));
  EXPECT_EQ(reverse_columns(ma).data, ea.data);
  EXPECT_EQ(reverse_columns(mb).data, eb.data);
}

// A hand case: a = (5, 5), b = (0, 2). mid = (2.5, 3.5); a's two pixels take
// the two ranks in either order: squared errors 0 or 1 + 1, mean 1 over 2
// pixels. Closed form: B_G = 3, A_G = 9.25; pixel 0: 9.25 - 15 + 6.25 = 0.5,
// pixel 1: 9.25 - 21 + 12.25 = 0.5.
TEST(RmseContrastInvariant, HandCaseWithOneGroup) {
  Image a(2, 1, 1, 5.0);
  Image b(2, 1, 1);
  b.data = {0.0, 2.0};
  EXPECT_DOUBLE_EQ(rmse_contrast_invariant(a, b, 0, 2), std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(rmse_contrast_invariant(b, a, 0, 2), std::sqrt(0.5));
}

// Every order of every group of equal values, on both sides: the mean squared
// error over all of them is the closed form exactly (up to rounding).
TEST(RmseContrastInvariant, IsTheMeanOverAllTieOrders) {
  struct Case {
    std::vector<double> a, b;
  };
  const std::vector<Case> cases = {
      {{1, 1, 1, 2, 2, 3}, {5, 5, 7, 7, 7, 9}},
      {{4, 0, 4, 0, 4, 4}, {1.5, -2, 8, 1.5, 3, 3}},
      {{2, 2, 2, 2, 2, 7}, {0, 1, 2, 3, 4, 5}},
      {{0, 1, 0, 1, 0, 1}, {6, 6, 6, 2, 2, 2}},
  };
  for (const Case& k : cases) {
    Image a(3, 2, 1);
    Image b(3, 2, 1);
    a.data.assign(k.a.begin(), k.a.end());
    b.data.assign(k.b.begin(), k.b.end());
    // Enumerate tie orders as permutations of 0..5 used as tie-breaking keys;
    // keep one per distinct rank assignment (each order of each group once).
    auto orders = [](const Image& image) {
      std::vector<std::vector<std::size_t>> seen;
      std::vector<std::vector<double>> keys;
      std::vector<double> perm = {0, 1, 2, 3, 4, 5};
      do {
        std::vector<std::size_t> pixels = {0, 1, 2, 3, 4, 5};
        std::sort(pixels.begin(), pixels.end(), [&](std::size_t i, std::size_t j) {
          return image.data[i] < image.data[j] ||
                 (image.data[i] == image.data[j] && perm[i] < perm[j]);
        });
        if (std::find(seen.begin(), seen.end(), pixels) == seen.end()) {
          seen.push_back(pixels);
          keys.push_back(perm);
        }
      } while (std::next_permutation(perm.begin(), perm.end()));
      return keys;
    };
    const auto a_orders = orders(a);
    const auto b_orders = orders(b);
    double sum = 0.0;
    for (const auto& oa : a_orders) {
      for (const auto& ob : b_orders) sum += squared_error_for_order(a, b, oa, ob);
    }
    const double mean_square = sum / static_cast<double>(a_orders.size() * b_orders.size()) / 6.0;
    const double ci = rmse_contrast_invariant(a, b, 0, 3);
    EXPECT_NEAR(ci * ci, mean_square, 1e-12 * mean_square)
        << a_orders.size() << " x " << b_orders.size() << " orders";
    EXPECT_NEAR(ci, closed_form_rmse_ci(a, b), 1e-13);
  }
}

// Many random tie orders (shuffled ranks inside each group, both sides): the
// mean squared error converges to the closed form within its standard error.
TEST(RmseContrastInvariant, RandomTieOrdersConvergeToIt) {
  const Image a = random_image(12, 10, 2, 13, 0.0, 7.0, true);   // 8 values: big groups
  const Image b = random_image(12, 10, 2, 14, 0.0, 40.0, true);  // smaller groups
  const double count = static_cast<double>(a.data.size());
  const int trials = 4000;
  std::mt19937_64 rng(15);
  std::vector<double> a_order(a.data.size());
  std::vector<double> b_order(b.data.size());
  double sum = 0.0;
  double sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    std::iota(a_order.begin(), a_order.end(), 0.0);
    std::iota(b_order.begin(), b_order.end(), 0.0);
    std::shuffle(a_order.begin(), a_order.end(), rng);
    std::shuffle(b_order.begin(), b_order.end(), rng);
    const double mse = squared_error_for_order(a, b, a_order, b_order) / count;
    sum += mse;
    sum2 += mse * mse;
  }
  const double mean = sum / trials;
  const double sd = std::sqrt((sum2 - trials * mean * mean) / (trials - 1));
  const double ci = rmse_contrast_invariant(a, b, 0, 12);
  const double standard_error = sd / std::sqrt(static_cast<double>(trials));
  ASSERT_GT(sd, 0.0);  // the orders matter here
  EXPECT_NEAR(ci * ci, mean, 4.0 * standard_error) << "z = " << (ci * ci - mean) / standard_error;
  // A fixed order (here: by pixel index) is one draw, not the centre.
  std::iota(a_order.begin(), a_order.end(), 0.0);
  const double by_index = squared_error_for_order(a, b, a_order, a_order) / count;
  EXPECT_GT(std::abs(by_index - ci * ci), 0.0);
}

// Mirroring, or any other rearrangement of the pixels (the same for a and b),
// gives the same bits. The images look like a noise-free run's: 8-bit ground
// truth, restored close to it with a third of its values tied (the order in
// which equal restored values are summed must not follow the pixels).
TEST(RmseContrastInvariant, DoesNotDependOnThePixelOrder) {
  for (unsigned seed = 16; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> gray(0.0, 255.0);
    std::normal_distribution<double> error(0.0, 2.0);
    Image a(300, 200, 2);
    Image b(300, 200, 2);
    for (std::size_t i = 0; i < a.data.size(); ++i) {
      a.data[i] = std::round(gray(rng));
      b.data[i] = a.data[i] + error(rng);
      if (i % 3 == 0) b.data[i] = std::round(4.0 * b.data[i]) / 4.0;
    }
    const double value = rmse_contrast_invariant(a, b, 20, 280);
    const Image ma = reverse_columns(a);
    const Image mb = reverse_columns(b);
    EXPECT_EQ(rmse_contrast_invariant(ma, mb, 20, 280), value) << "seed " << seed;
    EXPECT_EQ(rmse_contrast_invariant(ma, mb, 20, 280, 2), value) << "seed " << seed;
    // A random permutation of the pixels of each channel.
    const Image ca = crop_columns(a, 20, 260);
    const Image cb = crop_columns(b, 20, 260);
    Image pa = ca;
    Image pb = cb;
    std::vector<std::size_t> perm(ca.plane_size());
    std::iota(perm.begin(), perm.end(), std::size_t{0});
    for (int c = 0; c < 2; ++c) {
      std::shuffle(perm.begin(), perm.end(), rng);
      for (std::size_t p = 0; p < perm.size(); ++p) {
        pa.data[c * perm.size() + p] = ca.data[c * perm.size() + perm[p]];
        pb.data[c * perm.size() + p] = cb.data[c * perm.size() + perm[p]];
      }
    }
    EXPECT_EQ(rmse_contrast_invariant(pa, pb, 0, 260), value) << "seed " << seed;
    EXPECT_NEAR(value, closed_form_rmse_ci(ca, cb), 1e-12 * value) << "seed " << seed;
  }
}

TEST(RmseContrastInvariant, WithoutTiesIsPlainMidwayRmse) {
  const Image a = random_image(16, 8, 2, 9, 0.0, 255.0, false);
  const Image b = random_image(16, 8, 2, 10, 0.0, 255.0, false);
  const auto [ea, eb] = midway_equalize(crop_columns(a, 4, 9), crop_columns(b, 4, 9));
  EXPECT_NEAR(rmse_contrast_invariant(a, b, 4, 13), rmse(ea, eb, 0, 9), 1e-13);
  // Columns outside the window do not matter.
  Image a2 = a;
  for (int y = 0; y < 8; ++y) {
    a2.at(0, y, 0) = 1e6;
    a2.at(1, y, 15) = -1e6;
  }
  EXPECT_EQ(rmse_contrast_invariant(a2, b, 4, 13), rmse_contrast_invariant(a, b, 4, 13));
  EXPECT_GT(rmse_contrast_invariant(a, b, 4, 13), 0.0);
}

// With ties, RMSE_CI^2 exceeds the squared RMSE of the expected equalized
// images by the spread of mid inside the groups.
TEST(RmseContrastInvariant, WithTiesAddsTheSpreadInsideGroups) {
  const Image a = random_image(10, 6, 1, 19, 0.0, 5.0, true);
  const Image b = random_image(10, 6, 1, 20, 0.0, 100.0, false);
  const auto [ea, eb] = midway_equalize(a, b);
  const double ci = rmse_contrast_invariant(a, b, 0, 10);
  const double of_means = rmse(ea, eb, 0, 10);
  // b has no ties: the difference is sum over a's groups of the variance of mid.
  const auto mid = midway_values(a, b, 0);
  double spread = 0.0;
  for (std::size_t p = 0; p < a.data.size(); ++p) {
    const auto [first, last] = ranks_of(sorted_channel(a, 0), a.data[p]);
    double m1 = 0.0, m2 = 0.0;
    for (std::size_t i = first; i < last; ++i) {
      m1 += mid[i];
      m2 += mid[i] * mid[i];
    }
    const double size = static_cast<double>(last - first);
    spread += m2 / size - (m1 / size) * (m1 / size);
  }
  EXPECT_NEAR(ci * ci, of_means * of_means + spread / 60.0, 1e-9);
  EXPECT_GT(spread, 1.0);
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
  // The same groups on both sides: mid is constant in each group.
  EXPECT_EQ(rmse_contrast_invariant(a, affine, 0, 20), 0.0);
  EXPECT_EQ(rmse_contrast_invariant(a, square, 0, 20), 0.0);
  EXPECT_LT(rmse_contrast_invariant(square, cube_root, 3, 17), 1e-12);  // rounding of the means
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
  EXPECT_LT(rmse_contrast_invariant(a, b, 0, 12), 1e-12);
}

// Two threads and all hardware threads give the bits of one (below
// kParallelRmseCiPixels pixels a channel, as here, one thread works).
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

// A larger window: the two threads split b's sorted ranks at one of a's
// group starts (a bucket there is sorted first). Both ground truths
// (counted and sorted) give the bits of one thread.
TEST(RmseContrastInvariant, TwoThreadsOnALargeWindowGiveTheBitsOfOne) {
  for (const bool integers : {true, false}) {
    const Image a = random_image(720, 500, 1, 51, 0.0, 255.0, integers);
    const Image b = random_image(720, 500, 1, 52, -30.0, 290.0, false);
    const double one = rmse_contrast_invariant(a, b, 3, 717, 1);
    EXPECT_GT(one, 0.0);
    EXPECT_EQ(rmse_contrast_invariant(a, b, 3, 717, 2), one) << "integers " << integers;
  }
}

// A ground truth of integers in [0, 65535] is grouped by a histogram, any
// other by sorting: halving both images (exact in binary, and it halves every
// midway value, difference and square root exactly) moves the odd levels off
// the integers, so the second call sorts, and it must give exactly half.
TEST(RmseContrastInvariant, IntegerGroundTruthCountedAsSorted) {
  for (const double top : {255.0, 65535.0}) {
    Image a = random_image(300, 200, 3, 41, 0.0, top, true);
    a.data[7] = -0.0;  // the same level as +0
    const Image b = random_image(300, 200, 3, 42, -30.0, top + 30.0, false);
    Image half_a = a;
    Image half_b = b;
    for (double& v : half_a.data) v *= 0.5;
    for (double& v : half_b.data) v *= 0.5;
    const double counted = rmse_contrast_invariant(a, b, 10, 290, 1);
    EXPECT_GT(counted, 0.0);
    EXPECT_EQ(rmse_contrast_invariant(half_a, half_b, 10, 290, 1), 0.5 * counted);
  }
}

// Short runs, buckets sorted in cache and split in place, with values that
// share all but their lowest bits (an earlier radix sort dropped those bits
// from its keys), negatives, -0 and +0, huge and tiny magnitudes and
// integer ties: the plain closed form agrees.
TEST(RmseContrastInvariant, MatchesThePlainClosedFormOnAwkwardValues) {
  for (const auto& [width, height] : {std::pair{7, 5}, {40, 30}, {310, 211}, {700, 500}}) {
    Image a = random_image(width, height, 1, 21, -5.0, 260.0, true);
    Image b = random_image(width, height, 1, 22, -40.0, 300.0, false);
    std::mt19937_64 rng(23);
    for (std::size_t i = 0; i < b.data.size(); i += 7) {
      switch (rng() % 6) {
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
        case 4:  // 1 + k ulp: equal but for their lowest bits
          b.data[i] = 1.0 + std::ldexp(static_cast<double>(rng() % 4), -52);
          a.data[i] = 3.0 + std::ldexp(static_cast<double>(rng() % 4), -51);
          break;
        default:
          b.data[i] = std::round(b.data[i]);
          break;
      }
    }
    const double expected = closed_form_rmse_ci(a, b);
    EXPECT_NEAR(rmse_contrast_invariant(a, b, 0, width), expected, 1e-12 * expected)
        << width << "x" << height;
    EXPECT_EQ(rmse_contrast_invariant(reverse_columns(a), reverse_columns(b), 0, width),
              rmse_contrast_invariant(a, b, 0, width));
  }
}

// Values that differ only in their lowest bits (an earlier radix sort
// dropped those bits from its keys) form separate groups of the right
// sizes: two values on one side, all distinct on the other.
TEST(RmseContrastInvariant, ValuesEqualButForTheirLowestBitsAreDistinctGroups) {
  const Image spread = random_image(60, 40, 1, 24, 0.0, 255.0, false);
  Image near = random_image(60, 40, 1, 25, 0.0, 1.0, false);
  for (double& v : near.data) v = v < 0.5 ? 1.0 : 1.0 + std::ldexp(1.0, -52);
  for (const auto& [a, b] :
       {std::pair<const Image*, const Image*>{&spread, &near}, {&near, &spread}}) {
    const double expected = closed_form_rmse_ci(*a, *b);
    EXPECT_NEAR(rmse_contrast_invariant(*a, *b, 0, 60), expected, 1e-12 * expected);
  }
}

// The six reference settings (tests/fixtures/rmse_ci_ties.md): the
// noise-free RMSE_CI sits at the centre of the reference program's spread
// over random tie orders, within 4 standard errors of its 20-order mean.
TEST(RmseContrastInvariant, ReferenceCases) {
  std::istringstream table(test::read_file(test::fixture_path("rmse_ci_ties.md")));
  std::string line;
  int checked = 0;
  while (std::getline(table, line)) {
    if (line.rfind("| camera.png", 0) != 0 && line.rfind("| astronaut.png", 0) != 0) continue;
    std::vector<std::string> cells;
    std::istringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 9u) << line;
    auto trim = [](std::string s) {
      s.erase(0, s.find_first_not_of(' '));
      s.erase(s.find_last_not_of(' ') + 1);
      return s;
    };
    SimulationOptions options;
    options.noise = NoiseModel::kNone;
    options.mode = *shutter_mode_from_string(trim(cells[2]));
    options.velocity_px_per_slot = std::stod(cells[3]);
    options.dt = std::stod(cells[4]);
    const std::string spread = cells[7];
    const double mean = std::stod(spread.substr(0, spread.find("±")));
    const double sd = std::stod(spread.substr(spread.find("±") + std::string("±").size()));
    const double column_major = std::stod(cells[8]);
    const Image input = read_png(test::source_path("data/" + trim(cells[0])));
    const SimulationReport r = Simulate(options, input, *builtin_code(trim(cells[1])));
    const double value = r.metrics.rmse_ci;
    std::cout << line << "\n  -> " << std::setprecision(7) << value
              << ", z = " << (value - mean) / (sd / std::sqrt(20.0)) << "\n";
    EXPECT_NEAR(value, mean, 4.0 * sd / std::sqrt(20.0)) << line;
    EXPECT_GT(std::abs(value - column_major), 1e-6) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 6);
}

std::string hex_bits(double value) {
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << std::bit_cast<std::uint64_t>(value);
  return out.str();
}

// The bits of every case of the corpus (rmse_ci_corpus.h), with 1 and 2
// threads, as recorded in tests/fixtures/rmse_ci_corpus_bits.txt (made by
// the radix-sort implementation before the bucket sort, and unchanged
// since). FSS_RECORD_RMSE_CI_CORPUS=FILE writes the current bits to FILE
// instead of checking them.
TEST(RmseContrastInvariant, CorpusGivesTheRecordedBits) {
  const char* record = std::getenv("FSS_RECORD_RMSE_CI_CORPUS");
  std::map<std::string, std::string> recorded;
  if (record == nullptr) {
    std::istringstream lines(test::read_file(test::fixture_path("rmse_ci_corpus_bits.txt")));
    std::string name;
    std::string bits;
    while (lines >> name >> bits) recorded[name] = bits;
    ASSERT_GT(recorded.size(), 700u);
  }
  std::ostringstream written;
  std::size_t checked = 0;
  const std::size_t skipped = test::for_each_corpus_case([&](const test::CorpusCase& k) {
    const double one = rmse_contrast_invariant(k.a, k.a_offset, k.b, k.first, k.end, 1);
    // Under AddressSanitizer no case reaches kParallelRmseCiPixels: two threads would rerun one.
    const double two = test::kAddressSanitizer
                           ? one
                           : rmse_contrast_invariant(k.a, k.a_offset, k.b, k.first, k.end, 2);
    EXPECT_EQ(hex_bits(two), hex_bits(one)) << k.name;
    if (record != nullptr) {
      written << k.name << " " << hex_bits(one) << "\n";
      return;
    }
    const auto found = recorded.find(k.name);
    ASSERT_NE(found, recorded.end()) << k.name;
    EXPECT_EQ(hex_bits(one), found->second) << k.name << ": " << std::setprecision(17) << one;
    ++checked;
  });
  if (record != nullptr) {
    std::ofstream(record) << written.str();
    GTEST_SKIP() << "recorded the corpus's bits in " << record;
  }
  EXPECT_EQ(checked + skipped, recorded.size());
}

// The plain reference (sorts of pairs, every sum in rank order) gives the
// same bits on every case of the corpus.
TEST(RmseContrastInvariant, CorpusMatchesThePlainReferenceBitForBit) {
  test::for_each_corpus_case([&](const test::CorpusCase& k) {
    const double expected =
        test::reference_rmse_contrast_invariant(k.a, k.a_offset, k.b, k.first, k.end);
    EXPECT_EQ(hex_bits(rmse_contrast_invariant(k.a, k.a_offset, k.b, k.first, k.end, 2)),
              hex_bits(expected))
        << k.name << ": expected " << std::setprecision(17) << expected;
  });
}

// rmse_contrast_invariant against the plain reference, bit for bit, with
// 1 and 2 threads.
::testing::AssertionResult same_bits_as_reference(const Image& a, int a_offset, const Image& b,
                                                  int first, int end) {
  const std::string expected =
      hex_bits(test::reference_rmse_contrast_invariant(a, a_offset, b, first, end));
  for (const int threads : {1, 2}) {
    const std::string got = hex_bits(rmse_contrast_invariant(a, a_offset, b, first, end, threads));
    if (got != expected) {
      return ::testing::AssertionFailure()
             << threads << " thread(s): " << got << ", reference " << expected;
    }
  }
  return ::testing::AssertionSuccess();
}

// A window of width x height, 2 channels, with many ties on both sides: the
// ground truth (2 columns more on each side) at 17 levels, as 8-bit (kind
// 0), 16-bit as k / 257 (1), integers to 65535 (2) or floats (3); the
// restoration the level plus noise, a third rounded to quarters, a third to
// integers.
std::pair<Image, Image> random_ties(int width, int height, int kind, std::mt19937_64& rng) {
  Image a(width + 4, height, 2);
  Image b(width, height, 2);
  std::uniform_real_distribution<double> gray(0.0, 255.0);
  std::normal_distribution<double> noise(0.0, 2.5);
  for (int c = 0; c < 2; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const double level = std::round(gray(rng) / 16.0) * 16.0;
        const double ground[] = {level, std::round(level * 257.0 + 3.0) / 257.0, level * 257.0,
                                 static_cast<double>(static_cast<float>(level / 255.0))};
        a.at(c, y, x + 2) = ground[kind];
        const double restored = level + noise(rng);
        const double rounded[] = {std::round(4.0 * restored) / 4.0, std::round(restored), restored};
        b.at(c, y, x) = rounded[(x + y) % 3];
      }
    }
  }
  return {std::move(a), std::move(b)};
}

// Random windows with many ties on both sides, below and above the size at
// which two threads share the work: the reference's bits.
TEST(RmseContrastInvariant, MatchesThePlainReferenceOnRandomTies) {
  std::mt19937_64 rng(61);
  for (const auto& [width, height] : {std::pair{13, 7}, {150, 90}, {300, 400}}) {
    for (int kind = 0; kind < 4; ++kind) {
      const auto [a, b] = random_ties(width, height, kind, rng);
      EXPECT_TRUE(same_bits_as_reference(a, 2, b, 0, width))
          << width << "x" << height << ", kind " << kind;
    }
  }
}

// The bucket sort's edge cases: every value equal on one side or both, one
// huge outlier, +-1e300 (squares overflow), values spanning the doubles,
// denormals only, many equal restored values, b's runs of two (more than the
// one pass keeps: summed again), a single ground-truth group with two
// threads, one-pixel windows.
TEST(RmseContrastInvariant, MatchesThePlainReferenceOnBucketEdgeCases) {
  std::mt19937_64 rng(62);
  std::uniform_real_distribution<double> gray(0.0, 255.0);
  const std::vector<std::pair<std::string, std::function<double(std::size_t)>>> bs = {
      {"all equal", [](std::size_t) { return 7.5; }},
      {"one outlier", [&](std::size_t i) { return i == 4321 ? 1e150 : gray(rng); }},
      {"two outliers",
       [&](std::size_t i) { return i == 99     ? -1e150
                                   : i == 5000 ? 1e150
                                               : gray(rng); }},
      {"+-1e300", [&](std::size_t i) { return i % 9 == 0 ? (i % 2 ? 1e300 : -1e300) : gray(rng); }},
      {"whole range",
       [&](std::size_t i) { return i % 50 == 0 ? (i % 100 ? 1.7e308 : -1.7e308) : gray(rng); }},
      {"denormals", [&](std::size_t) { return static_cast<double>(rng() % 5000) * 4.9e-324; }},
      {"many equal", [&](std::size_t i) { return i % 4 == 0 ? gray(rng) : 128.0; }},
      {"pairs",
       [](std::size_t i) {
         const std::size_t pair = (i * 7919) % 20000 / 2;  // each value twice
         return static_cast<double>(pair) * 0.01;
       }},
      {"integers", [&](std::size_t) { return std::round(gray(rng)); }},
  };
  const std::vector<std::pair<std::string, std::function<double(std::size_t)>>> as = {
      {"8-bit", [&](std::size_t) { return std::round(gray(rng)); }},
      {"constant", [](std::size_t) { return 3.0; }},
      {"constant float", [](std::size_t) { return 0.3; }},
      {"float", [&](std::size_t) { return gray(rng) / 255.0; }},
  };
  for (const auto& [a_name, a_value] : as) {
    for (const auto& [b_name, b_value] : bs) {
      Image a(100, 200, 1);
      Image b(100, 200, 1);
      for (std::size_t i = 0; i < a.data.size(); ++i) {
        a.data[i] = a_value(i);
        b.data[i] = b_value(i);
      }
      EXPECT_TRUE(same_bits_as_reference(a, 0, b, 0, 100)) << a_name << ", " << b_name;
      EXPECT_TRUE(same_bits_as_reference(a, 0, b, 37, 38)) << a_name << ", " << b_name;
      const Image one_a = crop_columns(a, 5, 1);
      const Image one_b = crop_columns(b, 5, 1);
      EXPECT_TRUE(same_bits_as_reference(crop_columns(one_a, 0, 1), 0, one_b, 0, 1))
          << a_name << ", " << b_name;
    }
  }
  Image one_a(1, 1, 3);
  Image one_b(1, 1, 3);
  one_a.data = {-0.0, 5.0, 1e300};
  one_b.data = {0.0, -3.0, 4.9e-324};
  EXPECT_TRUE(same_bits_as_reference(one_a, 0, one_b, 0, 1));
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
