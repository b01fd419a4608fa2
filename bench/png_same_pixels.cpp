// Compares PNG files by their pixels, decoded with libpng as they are stored
// (no transformation: 16-bit samples stay 16-bit), not by their bytes: two
// encoders of the same image (another filter, another compressor) give
// different files with the same pixels. With two folders (as kept by
// `KEEP=DIR scripts/output_matrix.sh`), every .png under BEFORE is compared
// with the file of the same relative path under AFTER.
// Prints one line per file that differs, then a summary with the total sizes;
// exits 1 when any file differs or is missing.
// Usage: png_same_pixels BEFORE AFTER
#include <png.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Decoded {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, colour_type = 0;
  std::vector<std::uint8_t> samples;  // rows as stored, without filter bytes
};

// The file decoded by libpng (which checks every CRC and the zlib stream), or
// nothing with `error` set.
std::optional<Decoded> decode(const fs::path& path, std::string* error) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    *error = "cannot open";
    return std::nullopt;
  }
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  Decoded decoded;
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    *error = "libpng cannot decode it";
    return std::nullopt;
  }
  png_init_io(png, file);
  png_read_info(png, info);
  decoded.width = png_get_image_width(png, info);
  decoded.height = png_get_image_height(png, info);
  decoded.bit_depth = png_get_bit_depth(png, info);
  decoded.colour_type = png_get_color_type(png, info);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  decoded.samples.resize(row_bytes * decoded.height);
  rows.resize(decoded.height);
  for (png_uint_32 y = 0; y < decoded.height; ++y) rows[y] = decoded.samples.data() + y * row_bytes;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  return decoded;
}

// Why the two files differ, or "" when their pixels are the same.
std::string compare(const fs::path& before, const fs::path& after) {
  std::string error;
  const std::optional<Decoded> a = decode(before, &error);
  if (!a) return "before: " + error;
  const std::optional<Decoded> b = decode(after, &error);
  if (!b) return "after: " + error;
  if (a->width != b->width || a->height != b->height || a->bit_depth != b->bit_depth ||
      a->colour_type != b->colour_type) {
    return "header differs (size, bit depth or colour type)";
  }
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a->samples.size(); ++i) differing += a->samples[i] != b->samples[i];
  if (differing != 0) return std::to_string(differing) + " sample bytes differ";
  return "";
}

std::uintmax_t size_of(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  return ec ? 0 : size;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: png_same_pixels BEFORE AFTER (two PNG files or two folders)\n");
    return 2;
  }
  const fs::path before = argv[1], after = argv[2];
  std::vector<fs::path> relative;
  if (fs::is_directory(before)) {
    for (const auto& entry : fs::recursive_directory_iterator(before)) {
      if (entry.is_regular_file() && entry.path().extension() == ".png") {
        relative.push_back(fs::relative(entry.path(), before));
      }
    }
  } else {
    relative.emplace_back();
  }
  int differing = 0;
  std::uintmax_t bytes_before = 0, bytes_after = 0;
  for (const fs::path& name : relative) {
    const fs::path a = name.empty() ? before : before / name;
    const fs::path b = name.empty() ? after : after / name;
    const std::string why = fs::exists(b) ? compare(a, b) : "missing after";
    if (!why.empty()) {
      std::printf("%s: %s\n", a.c_str(), why.c_str());
      ++differing;
    }
    bytes_before += size_of(a);
    bytes_after += size_of(b);
  }
  std::printf("png_same_pixels: %zu PNG files, %d differ; %ju bytes before, %ju after\n",
              relative.size(), differing, bytes_before, bytes_after);
  return differing == 0 ? 0 : 1;
}
