#include "fss/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fss/error.h"

namespace fss {

namespace {
void require_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels) {
    throw_usage_error("images of different sizes cannot be compared: " + std::to_string(a.width) +
                      "x" + std::to_string(a.height) + "x" + std::to_string(a.channels) + " and " +
                      std::to_string(b.width) + "x" + std::to_string(b.height) + "x" +
                      std::to_string(b.channels));
  }
}

void require_window(const Image& a, int first, int end) {
  if (first < 0 || end > a.width || first >= end) {
    throw_usage_error("column window [" + std::to_string(first) + ", " + std::to_string(end) +
                      ") is empty or outside an image of width " + std::to_string(a.width));
  }
}
}  // namespace

double rmse(const Image& a, const Image& b, int first, int end) {
  require_same_size(a, b);
  require_window(a, first, end);
  double sum = 0.0;
  for (int c = 0; c < a.channels; ++c) {
    for (int y = 0; y < a.height; ++y) {
      const double* pa = a.row(c, y);
      const double* pb = b.row(c, y);
      for (int x = first; x < end; ++x) {
        const double d = pa[x] - pb[x];
        sum += d * d;
      }
    }
  }
  const double count = static_cast<double>(end - first) * a.height * a.channels;
  return std::sqrt(sum / count);
}

double psnr(double rmse_value) {
  // 10 log10(255^2 / RMSE^2)
  return 10.0 * std::log10(255.0 * 255.0 / (rmse_value * rmse_value));
}

std::pair<Image, Image> midway_equalize(const Image& a, const Image& b) {
  require_same_size(a, b);
  Image ea(a.width, a.height, a.channels);
  Image eb(b.width, b.height, b.channels);
  const std::size_t n = a.plane_size();
  const std::size_t w = static_cast<std::size_t>(a.width);
  const std::size_t h = static_cast<std::size_t>(a.height);
  // (value, column-major pixel index x * height + y): equal values are
  // ordered by that index. See metrics.h for why column-major.
  std::vector<std::pair<double, std::size_t>> sa(n);
  std::vector<std::pair<double, std::size_t>> sb(n);
  for (int c = 0; c < a.channels; ++c) {
    const double* pa = a.data.data() + c * n;
    const double* pb = b.data.data() + c * n;
    for (std::size_t y = 0; y < h; ++y) {
      for (std::size_t x = 0; x < w; ++x) {
        sa[y * w + x] = {pa[y * w + x], x * h + y};
        sb[y * w + x] = {pb[y * w + x], x * h + y};
      }
    }
    std::sort(sa.begin(), sa.end());
    std::sort(sb.begin(), sb.end());
    double* qa = ea.data.data() + c * n;
    double* qb = eb.data.data() + c * n;
    auto row_major = [&](std::size_t column_major) {
      return (column_major % h) * w + column_major / h;
    };
    for (std::size_t i = 0; i < n; ++i) {
      // the i-th smallest of each becomes the mean of the two i-th smallest
      const double mid = 0.5 * (sa[i].first + sb[i].first);
      qa[row_major(sa[i].second)] = mid;
      qb[row_major(sb[i].second)] = mid;
    }
  }
  return {std::move(ea), std::move(eb)};
}

double rmse_contrast_invariant(const Image& a, const Image& b, int first, int end) {
  require_same_size(a, b);
  require_window(a, first, end);
  const auto [ea, eb] =
      midway_equalize(crop_columns(a, first, end - first), crop_columns(b, first, end - first));
  return rmse(ea, eb, 0, ea.width);
}

Image residual_display(const Image& a, const Image& b) {
  require_same_size(a, b);
  Image d(a.width, a.height, a.channels);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    d.data[i] = a.data[i] - b.data[i];
    lo = std::min(lo, d.data[i]);
    hi = std::max(hi, d.data[i]);
  }
  // (d - min) / (max - min) * 255, every pixel including the first; dividing
  // first makes both ends exact (x / x = 1), which 255 / range * x is not.
  const double range = hi - lo;
  for (double& v : d.data) v = range > 0.0 ? (v - lo) / range * 255.0 : 0.0;
  return d;
}

}  // namespace fss
