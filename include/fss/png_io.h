// PNG reading and 8-bit PNG encoding (libpng). Conventions: image.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fss/image.h"

namespace fss {

// Largest width or height accepted when reading.
inline constexpr int kMaxImageSide = 1 << 16;

// Reads a PNG of any colour type (gray, gray+alpha, RGB, RGBA, palette) and
// bit depth (1..16), interlaced or not. Gray stays one channel, everything
// else becomes three; alpha is ignored. Throws a runtime fss::Error naming
// the file on any problem; libpng warnings are not errors and are dropped.
// With max_bytes > 0, an image whose decoding would need more memory than
// that is refused from its header, before anything is allocated (kLimit).
Image read_png(const std::filesystem::path& path, std::size_t max_bytes = 0);

// Same, from bytes in memory; `name` is used in error messages.
Image decode_png(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                 std::size_t max_bytes = 0);

// Memory that decoding a width x height image with `channels` (1 or 3
// after conversion) and `row_bytes` bytes a decoded row takes at its peak.
std::size_t png_decode_bytes(std::size_t width, std::size_t height, int channels,
                             std::size_t row_bytes);

// A value as an 8-bit PNG sample: rounded to the nearest integer (halves
// away from zero), clamped to [0, 255]; NaN gives 0.
std::uint8_t png8_sample(double value);

// Encodes an 8-bit gray (1 channel) or RGB (3 channels) PNG; each value
// becomes png8_sample(value).
std::vector<std::uint8_t> encode_png8(const Image& image);

// Same for an image given row by row: fill_row(c, y, row) writes the `width`
// values of channel c, row y. No full-size copy is made.
std::vector<std::uint8_t> encode_png8(
    int width, int height, int channels,
    const std::function<void(int c, int y, double* row)>& fill_row);

}  // namespace fss
