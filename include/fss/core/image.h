// The image type of fss and the conventions every fss function follows.
//
// Conventions (stated once here, not repeated in the other headers):
//  - Layout: planar doubles; channel c, row y, column x is
//    data[(c * height + y) * width + x]. Rows are the direction of motion.
//  - Scale: values are on the 0..255 scale of an 8-bit image. A 16-bit PNG is
//    divided by 257, keeping its fractional precision. Values are never
//    clamped inside the pipeline; only 8-bit encoding rounds and clamps.
//  - Channels: 1 (gray) or 3 (RGB); channels are always processed
//    independently and alpha is dropped when reading.
//  - Columns: functions taking a column range use half-open [first, end).
//  - Errors: bad arguments and unreadable data throw fss::Error (error.h).
//  - Threads: a `threads` argument of 0 means "all hardware threads"; results
//    never depend on it.
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
