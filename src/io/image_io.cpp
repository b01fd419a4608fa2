#include "fss/io/image_io.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"

namespace fss {

namespace {

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
  return format == ImageFileFormat::kTiff ? "TIFF" : "PNG";
}

std::optional<ImageFileFormat> image_file_format_from_string(std::string_view text) {
  if (text == "PNG") return ImageFileFormat::kPng;
  if (text == "TIFF") return ImageFileFormat::kTiff;
  return std::nullopt;
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
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error("input '" + name + "' is a directory, expected a PNG or TIFF file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw_runtime_error("cannot open input '" + name + "': " + std::strerror(errno));
  }
  // The signature first, so that what is neither format is refused after 8
  // bytes, even an endless stream such as /dev/zero.
  std::vector<std::uint8_t> bytes(8);
  file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(file.gcount()));
  if (file.bad()) throw_runtime_error("cannot read input '" + name + "'");
  if (bytes.empty()) {
    throw_runtime_error("input '" + name + "' is empty, expected a PNG or TIFF file");
  }
  if (has_png_signature(bytes.data(), bytes.size()) ||
      has_tiff_signature(bytes.data(), bytes.size())) {
    bytes.insert(bytes.end(), std::istreambuf_iterator<char>(file),
                 std::istreambuf_iterator<char>());
    if (file.bad()) throw_runtime_error("cannot read input '" + name + "'");
  }
  return decode_image(bytes.data(), bytes.size(), name, max_bytes, info);
}

}  // namespace fss
