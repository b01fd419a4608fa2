#include "fss/core/image.h"

#include <algorithm>
#include <string>

#include "fss/core/error.h"

namespace fss {

Image::Image(int width_px, int height_px, int channel_count, double fill)
    : width(width_px), height(height_px), channels(channel_count) {
  if (width_px < 0 || height_px < 0 || channel_count < 0) {
    throw_usage_error("image size " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                      "x" + std::to_string(channel_count) + " must not be negative");
  }
  data.assign(plane_size() * static_cast<std::size_t>(channel_count), fill);
}

Image crop_columns(const Image& image, int first, int count) {
  if (first < 0 || count < 0 || first + count > image.width) {
    throw_usage_error("column range [" + std::to_string(first) + ", " +
                      std::to_string(first + count) + ") is outside an image of width " +
                      std::to_string(image.width));
  }
  Image out(count, image.height, image.channels);
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      const double* src = image.row(c, y) + first;
      std::copy(src, src + count, out.row(c, y));
    }
  }
  return out;
}

Image scaled(const Image& image, double factor) {
  Image out = image;
  for (double& value : out.data) value *= factor;
  return out;
}

}  // namespace fss
