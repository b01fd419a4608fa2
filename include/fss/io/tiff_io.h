// TIFF reading and 32-bit float TIFF encoding (libtiff). Conventions: image.h.
//
// Reading accepts one image (a single page) of
//  - samples: 8- or 16-bit unsigned integers, or 32-bit IEEE floats;
//  - photometric interpretation min-is-black (gray, 1 channel) or RGB (3
//    channels); further samples (alpha) are ignored, as the PNG reader does;
//  - strips or tiles, samples contiguous or in separate planes;
//  - no compression, PackBits, LZW or Deflate (any predictor).
// Values, on the 0..255 scale of image.h: an 8-bit sample s is s, a 16-bit
// one s / 257 (as a 16-bit PNG), a float is taken as it is, so that the
// float TIFFs fssim writes read back as the gray levels they hold (a float
// image on [0, 1] must be multiplied by 255 first). Non-finite floats are
// refused. The Orientation tag is ignored (rows as stored, as in PNG).
// Anything else (palette, min-is-white, YCbCr, CMYK, signed or 64-bit
// samples, other compressions, several pages) is refused with one line
// naming the file. libtiff's own messages never reach stderr: an error
// becomes the fss::Error's message, warnings are dropped.
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

// Reads the TIFF in `bytes`; `name` is used in error messages. Throws a
// runtime fss::Error naming the file on any problem. Refuses from its header,
// before decoding: a side above kMaxImageSide (png_io.h), more pixels than
// the file can hold at its compression's largest ratio, and (max_bytes > 0)
// an image whose decoding needs more than max_bytes (kLimit). `samples`,
// when not null, receives how the file stores its samples.
Image decode_tiff(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                  std::size_t max_bytes = 0, TiffSamples* samples = nullptr);

// Same, from a file.
Image read_tiff(const std::filesystem::path& path, std::size_t max_bytes = 0);

// Encodes a 32-bit float TIFF (little-endian, uncompressed, contiguous
// samples, strips of about 8 KiB): gray (1 channel, min-is-black) or RGB (3
// channels). fill_row(c, y, row) writes the `width` values of channel c, row
// y; each is stored as the nearest float, unclamped (negative values, values
// above 255, infinities and NaN stay as they are). The same values give the
// same bytes.
std::vector<std::uint8_t> encode_tiff_float(
    int width, int height, int channels,
    const std::function<void(int c, int y, double* row)>& fill_row);

// Same for an image.
std::vector<std::uint8_t> encode_tiff_float(const Image& image);

}  // namespace fss
