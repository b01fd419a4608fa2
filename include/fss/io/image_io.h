// Reading an input image, PNG or TIFF, told apart by its signature whatever its name (what each
// format accepts: png_io.h, tiff_io.h). Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "fss/core/image.h"

namespace fss {

enum class ImageFileFormat { kPng, kTiff };
std::string to_string(ImageFileFormat format);  // "PNG", "TIFF"
std::optional<ImageFileFormat> image_file_format_from_string(std::string_view text);

// How an input file stores its samples.
struct ImageFileInfo {
  ImageFileFormat format = ImageFileFormat::kPng;
  int bits_per_sample = 8;  // 1 to 16 (PNG), 8, 16 or 32 (TIFF)
  bool floating = false;    // 32-bit float TIFF
};

// Reads the PNG or TIFF file at `path` (decode_png, decode_tiff), refusing a directory and
// anything else after its first 8 bytes (even an endless stream). `info`, when not null, receives
// how the file stores its samples. Errors as decode_png's and decode_tiff's.
Image read_image(const std::filesystem::path& path, std::size_t max_bytes = 0,
                 ImageFileInfo* info = nullptr);

// Same, from bytes in memory; `name` is used in error messages.
Image decode_image(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                   std::size_t max_bytes = 0, ImageFileInfo* info = nullptr);

}  // namespace fss
