// Private to src/io: the PNG writer of the image outputs (PngCompression::
// kImage). The file is written here from the PNG specification (signature,
// IHDR, IDAT and IEND chunks, each with its CRC-32); the zlib stream inside
// the IDAT chunks is compressed by ISA-L's igzip at level 1, over blocks of
// rows, so that no copy of the whole image is made.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/png_io.h"

namespace fss::detail {

// An image as a PNG stores it.
struct PngRaster {
  int width = 0;
  int height = 0;
  int channels = 1;   // 1 (gray) or 3 (RGB)
  int bit_depth = 8;  // 8 or 16
  // Bytes of a row: its interleaved samples, 16-bit ones big-endian.
  std::size_t row_bytes() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(channels) *
           static_cast<std::size_t>(bit_depth / 8);
  }
};

// Row y as the PNG stores it (row_bytes() bytes): either written into
// `scratch` (room for one row), which is then returned, or a pointer to the
// row held elsewhere, valid until the encoding returns. Called once a row,
// in order from the top.
using StoredRowSource = std::function<const std::uint8_t*(int y, std::uint8_t* scratch)>;

// The PNG file of `raster` (checked by the caller: 1 or 3 channels, 8 or 16
// bits, width and height > 0), every row with the average filter, as a
// std::vector<std::uint8_t> or a std::string (what an output file holds).
// The same rows give the same bytes, on any thread (see png_write.cpp for
// the processors). Throws a runtime fss::Error when memory runs out or the
// compressor fails; an exception of `rows` goes through unchanged.
template <class Bytes>
Bytes write_png(const PngRaster& raster, const StoredRowSource& rows);

extern template std::vector<std::uint8_t> write_png(const PngRaster&, const StoredRowSource&);
extern template std::string write_png(const PngRaster&, const StoredRowSource&);

// encode_png's bytes (PngCompression::kImage) as a std::string, the bytes
// of an output file, without a copy of the file (png_io.cpp).
std::string encode_png_string(int width, int height, int channels,
                              const std::function<void(int c, int y, double* row)>& fill_row,
                              PngDepth depth);
std::string encode_png_string(const Image& image, PngDepth depth);
std::string encode_png8_samples_string(int width, int height, int channels,
                                       std::span<const std::uint8_t> samples);

// PNG's average filter (type 3) of row `current` over `previous` (zeros for
// the first row): out[i] = current[i] - floor((current[i - bpp] + previous[i]) / 2),
// with current[i - bpp] = 0 for i < bpp. Exposed for its test.
void average_filter(const std::uint8_t* current, const std::uint8_t* previous,
                    std::size_t row_bytes, std::size_t bytes_per_pixel, std::uint8_t* out);

}  // namespace fss::detail
