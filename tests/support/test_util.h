// Helpers shared by the tests: temporary directories, files, synthetic
// images and running the fssim binary.
#pragma once

#include <png.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"

namespace fss::test {

// A fresh empty directory under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& bytes);

// Names of the entries of a directory, sorted.
std::vector<std::string> list_directory(const std::filesystem::path& dir);

struct CommandResult {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;
  std::string err;
};
// Runs `command` through /bin/sh with stdout and stderr captured.
CommandResult run_command(const std::string& command);

// Runs the fssim binary under test with the given arguments (shell-quoted by
// the caller where needed).
CommandResult run_fssim(const std::string& arguments);

// Deterministic test image with edges, smooth ramps and texture; values in
// [0, 255].
Image make_test_image(int width, int height, int channels, std::uint64_t seed = 1);

// The fss::Error thrown by f(), if any.
template <typename F>
std::optional<Error> error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  return std::nullopt;
}

// A path in single quotes, for a command line run by run_command.
std::string quote(const std::filesystem::path& path);

// The lines of `text`, without their line ends.
std::vector<std::string> lines_of(const std::string& text);

// A PNG to craft with libpng itself, in any format libpng writes.
struct PngSpec {
  int width = 0;
  int height = 0;
  int bit_depth = 8;
  int color_type = PNG_COLOR_TYPE_GRAY;
  bool interlaced = false;
  std::vector<png_color> palette;  // for PNG_COLOR_TYPE_PALETTE
  // Packed rows exactly as stored in a PNG (16-bit samples big-endian,
  // sub-byte samples leftmost pixel in the high bits).
  std::vector<std::vector<std::uint8_t>> rows;
};

// The PNG file `spec` describes; a test failure (and no bytes) if libpng
// refuses it.
std::vector<std::uint8_t> craft_png(const PngSpec& spec);

// Repository paths.
std::filesystem::path source_path(const std::string& relative);
std::filesystem::path fixture_path(const std::string& relative);

}  // namespace fss::test
