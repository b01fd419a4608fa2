// The image type of fss: planar doubles on the 0..255 scale (conventions: fss/fss.h).
#pragma once

#include <cstddef>
#include <vector>

namespace fss {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<double> data;

  Image() = default;
  Image(int width_px, int height_px, int channel_count, double fill = 0.0);

  std::size_t plane_size() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  double* row(int c, int y) {
    return data.data() + (static_cast<std::size_t>(c) * height + y) * width;
  }
  const double* row(int c, int y) const {
    return data.data() + (static_cast<std::size_t>(c) * height + y) * width;
  }
  double& at(int c, int y, int x) { return row(c, y)[x]; }
  double at(int c, int y, int x) const { return row(c, y)[x]; }
};

// Columns [first, first + count) of every row; throws if out of range.
Image crop_columns(const Image& image, int first, int count);

// Every value multiplied by `factor`.
Image scaled(const Image& image, double factor);

}  // namespace fss
