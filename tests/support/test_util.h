// Helpers shared by the tests: temporary directories, files, synthetic
// images and running the fssim binary.
#pragma once

#include <png.h>

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
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

// The one way tests expect an error: f() must throw an fss::Error of `kind`
// whose message contains each of `parts`. Use as
//   EXPECT_TRUE(test::throws_error([&] { ... }, ErrorKind::kUsage, {"dt", "> 0"}));
template <typename F>
::testing::AssertionResult throws_error(F&& f, ErrorKind kind,
                                        std::initializer_list<std::string_view> parts = {}) {
  const std::optional<Error> error = error_of(std::forward<F>(f));
  if (!error) return ::testing::AssertionFailure() << "no fss::Error was thrown";
  if (error->kind() != kind) {
    return ::testing::AssertionFailure() << "wrong error kind for: " << error->what();
  }
  for (const std::string_view part : parts) {
    if (std::string_view(error->what()).find(part) == std::string_view::npos) {
      return ::testing::AssertionFailure() << "'" << part << "' is not in: " << error->what();
    }
  }
  return ::testing::AssertionSuccess() << error->what();
}

// The gains of one of the paper's six codes (snapshot, accumulation, raskar,
// random, mip, sinc) as tests/fixtures/paper_codes.txt lists them: the
// published values, independent of the library's embedded codes/.
std::vector<double> paper_gains(const std::string& name);

// max |a - b| over all samples; a and b must have the same size.
double max_abs_difference(const Image& a, const Image& b);
double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b);

// True in a build with AddressSanitizer (scripts/test-sanitize.sh). It
// reserves terabytes of address space, so no RLIMIT_AS test can run there,
// and its shadow memory and quarantine roughly double a process's peak.
inline constexpr bool kAddressSanitizer =
#if defined(__SANITIZE_ADDRESS__)
    true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    true;
#else
    false;
#endif
#else
    false;
#endif

// Limits the address space (RLIMIT_AS) of the calling process to its
// present size plus `extra` bytes; exits with status 2 when it cannot (for
// the body of a death test).
void limit_address_space(std::size_t extra);

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
