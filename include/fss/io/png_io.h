// PNG reading (libpng) and 8- or 16-bit PNG encoding (ISA-L for images, libpng for plots).
// Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fss/core/image.h"

namespace fss {

// Largest width or height accepted when reading.
inline constexpr int kMaxImageSide = 1 << 16;

// Reads a PNG of any colour type and bit depth (1..16), interlaced or not: gray stays one
// channel, everything else becomes three, alpha is ignored. Throws a runtime fss::Error naming
// the file on any problem (libpng's warnings are dropped); with max_bytes > 0, a kLimit one from
// the header, before anything is allocated, when decoding would need more than max_bytes.
Image read_png(const std::filesystem::path& path, std::size_t max_bytes = 0);

// Same, from bytes in memory; `name` is used in error messages.
Image decode_png(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                 std::size_t max_bytes = 0);

// Peak memory of decoding a width x height image of `channels` (1 or 3 after conversion) with
// `row_bytes` bytes a decoded row.
std::size_t png_decode_bytes(std::size_t width, std::size_t height, int channels,
                             std::size_t row_bytes);

// How an encoded PNG is compressed; the pixels are the same, only file size and encoding time
// differ. kImage suits images (ISA-L; the bytes never depend on the thread, but do on ISA-L's
// version and on whether the processor has SSE4.2); kGraphics suits plots (libpng and zlib).
enum class PngCompression { kImage, kGraphics };

// A value as an 8-bit PNG sample: rounded to the nearest integer (halves away from zero) and
// clamped to [0, 255], as std::clamp(std::round(value), 0.0, 255.0) without a libm call; NaN
// gives 0.
inline std::uint8_t png8_sample(double value) {
  if (!(value >= 0.5)) return 0;  // negatives, [0, 0.5) and NaN
  if (value >= 255.0) return 255;
  const int whole = static_cast<int>(value);  // truncation; exact in [0.5, 255)
  return static_cast<std::uint8_t>(whole + (value - whole >= 0.5 ? 1 : 0));
}

// A value as a 16-bit PNG sample: value x 257 rounded to the nearest integer (halves away from
// zero), clamped to [0, 65535]; NaN gives 0. A value read from a 16-bit PNG gives back its sample
// exactly; an integer gray level g gives 257 g, the 16-bit sample of the same brightness.
inline std::uint16_t png16_sample(double value) {
  const double scaled = value * 257.0;
  if (!(scaled >= 0.5)) return 0;  // negatives, [0, 0.5) and NaN
  if (scaled >= 65535.0) return 65535;
  const int whole = static_cast<int>(scaled);  // truncation; exact in [0.5, 65535)
  return static_cast<std::uint16_t>(whole + (scaled - whole >= 0.5 ? 1 : 0));
}

// Bits per sample of an encoded image PNG.
enum class PngDepth { k8, k16 };
std::string to_string(PngDepth depth);  // "8", "16"
std::optional<PngDepth> png_depth_from_string(std::string_view text);

// The size a PNG file's header (IHDR) declares, without decoding: channels as read_png gives
// them, and the bits per sample. Nothing when the file does not start with a PNG signature and an
// IHDR or is not a regular file (a pipe is read once, by read_png): read_png then says why.
struct PngHeaderSize {
  int width = 0;
  int height = 0;
  int channels = 0;
  int bit_depth = 8;
};
std::optional<PngHeaderSize> read_png_header_size(const std::filesystem::path& path);

// Encodes an 8-bit gray (1 channel) or RGB (3 channels) PNG; each value
// becomes png8_sample(value).
std::vector<std::uint8_t> encode_png8(const Image& image,
                                      PngCompression compression = PngCompression::kImage);

// Same for an image given row by row: fill_row(c, y, row) writes the `width`
// values of channel c, row y. The only full-size copy is of 8-bit samples.
std::vector<std::uint8_t> encode_png8(
    int width, int height, int channels,
    const std::function<void(int c, int y, double* row)>& fill_row,
    PngCompression compression = PngCompression::kImage);

// Same at `depth` bits a sample: PngDepth::k8 gives encode_png8's bytes,
// PngDepth::k16 stores png16_sample(value) of each value.
std::vector<std::uint8_t> encode_png(int width, int height, int channels,
                                     const std::function<void(int c, int y, double* row)>& fill_row,
                                     PngDepth depth,
                                     PngCompression compression = PngCompression::kImage);
std::vector<std::uint8_t> encode_png(const Image& image, PngDepth depth,
                                     PngCompression compression = PngCompression::kImage);

// Same for 8-bit samples already interleaved as PNG stores them (gray, or
// RGB triplets; rows top down, width x channels bytes each).
std::vector<std::uint8_t> encode_png8_samples(int width, int height, int channels,
                                              std::span<const std::uint8_t> samples,
                                              PngCompression compression = PngCompression::kImage);

}  // namespace fss
