// Image files: fss.read_png, read_tiff, read_image, write_png, write_tiff (their docstrings:
// image_docs.h). Readers return the samples as the file stores them (uint8, uint16 or float32),
// which simulate(..., data_range=None) reads as fssim reads the file; writers go through the
// library's encoders and its atomic write (io/safe_write.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "bindings.h"
#include "convert.h"
#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/image_io.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "image_docs.h"
#include "io/input_bytes.h"
#include "io/safe_write.h"

namespace fss::python {
namespace {

// ---------------------------------------------------------------------------
// Reading

enum class FileFormat { kPng, kTiff, kEither };

constexpr std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

bool has_png_signature(const std::uint8_t* bytes, std::size_t size) {
  return size >= sizeof kPngSignature && std::memcmp(bytes, kPngSignature, 8) == 0;
}

// The decoded image (gray levels, as fssim reads the file) and how the file stores its samples.
struct DecodedFile {
  fss::Image image;
  fss::ImageFileInfo info;
};

// Reads and decodes `path` as `format` (a PNG reader refuses a TIFF and the other way round),
// bounded by max_bytes (0: no limit) before anything is decoded.
DecodedFile decode_file(const std::string& path, FileFormat format, std::size_t max_bytes) {
  DecodedFile decoded;
  if (format == FileFormat::kEither) {
    decoded.image = fss::read_image(path, max_bytes, &decoded.info);
    return decoded;
  }
  const bool png = format == FileFormat::kPng;
  const std::vector<std::uint8_t> bytes =
      fss::detail::read_input_bytes(path, png ? "a PNG file" : "a TIFF file",
                                    png ? has_png_signature : fss::has_tiff_signature, max_bytes);
  if (png && !has_png_signature(bytes.data(), bytes.size())) {
    fss::decode_png(bytes.data(), bytes.size(), path, max_bytes);  // refuses it, naming the file
  }
  if (png) {
    decoded.image = fss::decode_image(bytes.data(), bytes.size(), path, max_bytes, &decoded.info);
    return decoded;
  }
  fss::TiffSamples samples;
  decoded.image = fss::decode_tiff(bytes.data(), bytes.size(), path, max_bytes, &samples);
  decoded.info = {fss::ImageFileFormat::kTiff, samples.bits_per_sample, samples.floating};
  return decoded;
}

// A sample's value (gray level) as the file stored it: 8-bit s is s, 16-bit s / 257 gives back s
// (png16_sample), a float sample its float.
template <typename T>
T stored_sample(double value) {
  if constexpr (std::is_same_v<T, std::uint8_t>) return static_cast<std::uint8_t>(value);
  if constexpr (std::is_same_v<T, std::uint16_t>) return fss::png16_sample(value);
  if constexpr (std::is_same_v<T, float>) return static_cast<float>(value);
}

template <typename T>
py::array stored_array(const fss::Image& image) {
  std::vector<py::ssize_t> shape = {image.height, image.width};
  if (image.channels != 1) shape.push_back(image.channels);
  py::array_t<T> array(shape);
  T* target = array.mutable_data();
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) *target++ = stored_sample<T>(image.at(c, y, x));
    }
  }
  return array;
}

// The decoded image as the file's samples: uint8 (PNG of 1 to 8 bits, palettes included; 8-bit
// TIFF), uint16 (16 bits) or float32 (float TIFF). The array is allocated while the decoded image
// lives: both within max_bytes (a limit error naming the file otherwise).
py::array native_array(const DecodedFile& decoded, const std::string& path, std::size_t max_bytes) {
  const fss::Image& image = decoded.image;
  const std::size_t samples = static_cast<std::size_t>(image.width) * image.height * image.channels;
  const std::size_t itemsize =
      decoded.info.floating ? sizeof(float) : (decoded.info.bits_per_sample > 8 ? 2 : 1);
  fss::detail::check_decoding_memory(path, image.width, image.height,
                                     samples * (sizeof(double) + itemsize), max_bytes);
  if (decoded.info.floating) return stored_array<float>(image);
  if (decoded.info.bits_per_sample > 8) return stored_array<std::uint16_t>(image);
  return stored_array<std::uint8_t>(image);
}

std::size_t memory_limit(const py::object& max_memory) {
  const std::uint64_t limit = uint64_argument(max_memory, "max_memory", " (bytes; 0: no limit)");
  return static_cast<std::size_t>(std::min<std::uint64_t>(limit, SIZE_MAX));
}

py::array read_file(const py::object& path_object, const py::object& max_memory,
                    FileFormat format) {
  const std::string path = path_argument(path_object, "path");
  const std::size_t limit = memory_limit(max_memory);
  DecodedFile decoded;
  {
    py::gil_scoped_release release;
    decoded = decode_file(path, format, limit);
  }
  return native_array(decoded, path, limit);
}

// ---------------------------------------------------------------------------
// Writing

// The PNG depth of bit_depth= (8 or 16).
fss::PngDepth png_depth_argument(const py::object& bit_depth) {
  const long long bits = int_argument(bit_depth, "bit_depth");
  if (bits != 8 && bits != 16) {
    throw py::value_error("bit_depth = " + std::to_string(bits) + ": must be 8 or 16");
  }
  return bits == 8 ? fss::PngDepth::k8 : fss::PngDepth::k16;
}

// Writes `bytes` to `path` whole or not at all (a hidden temporary renamed over it).
void write_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  fss::write_file_safely(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void write_png(const py::object& path_object, const py::object& image_object,
               const py::object& data_range, const py::object& bit_depth) {
  const std::string path = path_argument(path_object, "path");
  const fss::PngDepth depth = png_depth_argument(bit_depth);
  const fss::Image image = image_argument(image_object, data_range, "image");
  py::gil_scoped_release release;
  write_atomically(path, fss::encode_png(image, depth));
}

void write_tiff(const py::object& path_object, const py::object& image_object,
                const py::object& data_range) {
  const std::string path = path_argument(path_object, "path");
  const fss::Image image = image_argument(image_object, data_range, "image");
  py::gil_scoped_release release;
  write_atomically(path, fss::encode_tiff_float(image));
}

}  // namespace

void define_images(py::module_& m) {
  m.def(
      "read_png",
      [](const py::object& path, const py::object& max_memory) {
        return read_file(path, max_memory, FileFormat::kPng);
      },
      py::arg("path"), py::kw_only(), py::arg("max_memory") = 0, kReadPngDoc);
  m.def(
      "read_tiff",
      [](const py::object& path, const py::object& max_memory) {
        return read_file(path, max_memory, FileFormat::kTiff);
      },
      py::arg("path"), py::kw_only(), py::arg("max_memory") = 0, kReadTiffDoc);
  m.def(
      "read_image",
      [](const py::object& path, const py::object& max_memory) {
        return read_file(path, max_memory, FileFormat::kEither);
      },
      py::arg("path"), py::kw_only(), py::arg("max_memory") = 0, kReadImageDoc);
  m.def("write_png", &write_png, py::arg("path"), py::arg("image"), py::kw_only(),
        py::arg("data_range") = py::none(), py::arg("bit_depth") = 8, kWritePngDoc);
  m.def("write_tiff", &write_tiff, py::arg("path"), py::arg("image"), py::kw_only(),
        py::arg("data_range") = py::none(), kWriteTiffDoc);
}

}  // namespace fss::python
