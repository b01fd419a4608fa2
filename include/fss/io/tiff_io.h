// TIFF reading and 32-bit float TIFF encoding (libtiff, whose messages never reach stderr).
// Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fss/core/image.h"

namespace fss {

// True when `bytes` start as a TIFF or BigTIFF file does ("II*\0", "MM\0*",
// "II+\0", "MM\0+").
bool has_tiff_signature(const std::uint8_t* bytes, std::size_t size);

// How a TIFF stores its samples (what decode_tiff read).
struct TiffSamples {
  int bits_per_sample = 0;  // 8, 16 or 32
  bool floating = false;    // 32-bit IEEE float
};

// Reads the TIFF in `bytes`; `name` is used in error messages. Accepts one page of 8- or 16-bit
// unsigned or 32-bit float samples, gray (min-is-black) or RGB (further samples such as alpha
// ignored), in strips or tiles, contiguous or planar, uncompressed, PackBits, LZW or Deflate (any
// predictor). Values: an 8-bit sample s is s, a 16-bit one s / 257, a float as it is (scale a
// [0, 1] image by 255 first); the Orientation tag is ignored. Throws a runtime fss::Error naming
// the file for anything else, a non-finite float or any problem; refuses from the header, before
// decoding, a side above kMaxImageSide (png_io.h), more pixels than the file can hold, and
// (max_bytes > 0) a decoding over max_bytes (kLimit). `samples`, when not null, receives how the
// file stores them.
Image decode_tiff(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                  std::size_t max_bytes = 0, TiffSamples* samples = nullptr);

// Same, from a file.
Image read_tiff(const std::filesystem::path& path, std::size_t max_bytes = 0);

// Encodes a 32-bit float TIFF (little-endian, uncompressed), gray (1 channel) or RGB (3).
// fill_row(c, y, row) writes the `width` values of channel c, row y; each is stored as the
// nearest float, unclamped (negatives, values above 255, infinities and NaN stay). The same values
// give the same bytes. Throws a usage fss::Error for other channel counts or a side outside
// [1, kMaxImageSide].
std::vector<std::uint8_t> encode_tiff_float(
    int width, int height, int channels,
    const std::function<void(int c, int y, double* row)>& fill_row);

// Same for an image.
std::vector<std::uint8_t> encode_tiff_float(const Image& image);

}  // namespace fss
