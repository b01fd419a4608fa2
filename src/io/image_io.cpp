#include "fss/io/image_io.h"

#include <cstring>
#include <vector>

#include "core/enum_names.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "io/input_bytes.h"

namespace fss {

namespace {

constexpr detail::EnumNames<ImageFileFormat, 2> kImageFileFormatNames{
    {{ImageFileFormat::kPng, "PNG"}, {ImageFileFormat::kTiff, "TIFF"}}};

constexpr std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

bool has_png_signature(const std::uint8_t* bytes, std::size_t size) {
  return size >= 8 && std::memcmp(bytes, kPngSignature, 8) == 0;
}

// The bit depth of a PNG's IHDR (the first chunk: 8 signature bytes, length,
// type, width, height, then the depth); 8 when the file is too short (it is
// refused then).
int png_bit_depth(const std::uint8_t* bytes, std::size_t size) {
  constexpr std::size_t kDepthOffset = 8 + 4 + 4 + 4 + 4;
  return size > kDepthOffset ? bytes[kDepthOffset] : 8;
}

}  // namespace

std::string to_string(ImageFileFormat format) {
  return detail::enum_name(kImageFileFormatNames, format);
}

std::optional<ImageFileFormat> image_file_format_from_string(std::string_view text) {
  return detail::enum_from_name(kImageFileFormatNames, text);
}

Image decode_image(const std::uint8_t* bytes, std::size_t size, const std::string& name,
                   std::size_t max_bytes, ImageFileInfo* info) {
  if (has_png_signature(bytes, size)) {
    Image image = decode_png(bytes, size, name, max_bytes);
    if (info != nullptr) *info = {ImageFileFormat::kPng, png_bit_depth(bytes, size), false};
    return image;
  }
  if (has_tiff_signature(bytes, size)) {
    TiffSamples samples;
    Image image = decode_tiff(bytes, size, name, max_bytes, &samples);
    if (info != nullptr) {
      *info = {ImageFileFormat::kTiff, samples.bits_per_sample, samples.floating};
    }
    return image;
  }
  throw_runtime_error("input '" + name + "' is not a PNG or TIFF file (bad signature)");
}

Image read_image(const std::filesystem::path& path, std::size_t max_bytes, ImageFileInfo* info) {
  const std::vector<std::uint8_t> bytes = detail::read_input_bytes(
      path, "a PNG or TIFF file",
      [](const std::uint8_t* head, std::size_t size) {
        return has_png_signature(head, size) || has_tiff_signature(head, size);
      },
      max_bytes);
  return decode_image(bytes.data(), bytes.size(), path.string(), max_bytes, info);
}

}  // namespace fss
