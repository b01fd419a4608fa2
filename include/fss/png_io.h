// PNG reading and 8-bit PNG encoding (libpng). Conventions: image.h.
#pragma once

#include <cstdint>
#include <filesystem>
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
Image read_png(const std::filesystem::path& path);

// Same, from bytes in memory; `name` is used in error messages.
Image decode_png(const std::uint8_t* bytes, std::size_t size, const std::string& name);

// Encodes an 8-bit gray (1 channel) or RGB (3 channels) PNG; each value is
// rounded to the nearest integer and clamped to [0, 255].
std::vector<std::uint8_t> encode_png8(const Image& image);

}  // namespace fss
