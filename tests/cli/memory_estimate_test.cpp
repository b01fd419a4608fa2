// The memory estimate against the measured peak (issue 12): for gray and RGB
// images, both modes and the options that add memory (--sheet, --report,
// --trials, --png-depth 16), the estimate fssim states when it refuses a run
// (estimate_working_memory_bytes with the outputs' bytes) must be at or
// above the peak resident memory of the same run (getrusage of the child).
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "support/test_util.h"

extern char** environ;

namespace fss {
namespace {

namespace fs = std::filesystem;

// Peak resident memory, in bytes, of fssim run with `arguments` (split at
// spaces), or -1 when it could not run or did not exit 0.
double peak_bytes(const std::string& arguments) {
  std::vector<std::string> words = {FSSIM_BINARY_PATH};
  std::istringstream in(arguments);
  for (std::string word; in >> word;) words.push_back(word);
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t child = 0;
  const int spawned = posix_spawn(&child, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1.0;
  int status = 0;
  rusage usage{};
  if (wait4(child, &status, 0, &usage) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return -1.0;
  }
  return static_cast<double>(usage.ru_maxrss) * 1024.0;  // ru_maxrss is in KiB
}

// The size after `prefix` in `text` ("needs about 162.7 MiB"), less half of
// its last digit (a lower bound of the exact size), or 0 when there is none.
double stated_bytes(const std::string& text, const std::string& prefix) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(prefix + R"( ([0-9.]+) (bytes|KiB|MiB|GiB))"))) {
    return 0.0;
  }
  const double units[] = {1.0, 1024.0, 1024.0 * 1024.0, 1024.0 * 1024.0 * 1024.0};
  const std::string unit = m[2];
  const double scale = units[unit == "bytes" ? 0 : unit == "KiB" ? 1 : unit == "MiB" ? 2 : 3];
  return (std::stod(m[1]) - 0.05) * scale;
}

// The estimate in fssim's refusal under --max-memory `limit` bytes.
double stated_estimate_bytes(const std::string& arguments, double limit = 1.0) {
  const test::CommandResult r =
      test::run_fssim(arguments + " --max-memory " + std::to_string(static_cast<long long>(limit)));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const double estimate = stated_bytes(r.err, "needs about");
  if (estimate == 0.0) ADD_FAILURE() << "no estimate in: " << r.err;
  return estimate;
}

class MemoryEstimate : public ::testing::TestWithParam<int> {};

TEST_P(MemoryEstimate, IsAtOrAboveTheMeasuredPeak) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's own memory would be measured";
  const int channels = GetParam();
  test::TempDir dir;
  const fs::path input = dir / "input.png";
  // Large enough that the images, not the libraries, make the peak.
  const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(1600, 1000, channels));
  test::write_file(input, std::string(png.begin(), png.end()));
  for (const char* mode : {"numerical", "analog"}) {
    for (const char* options :
         {"", "--sheet", "--report", "--trials 3", "--sheet --report --trials 3", "--no-plots"}) {
      const std::string arguments = "-i " + input.string() + " -o " + (dir / "out").string() +
                                    " --threads 2 --mode " + mode + " " + options;
      const double estimate = stated_estimate_bytes(arguments);
      const double peak = peak_bytes(arguments + " --max-memory 0");
      ASSERT_GT(peak, 0.0) << arguments;
      std::printf("memory estimate: %d channel(s), %-9s %-28s estimate %7.1f MiB, peak %7.1f MiB\n",
                  channels, mode, options, estimate / 1048576.0, peak / 1048576.0);
      EXPECT_GE(estimate, peak) << arguments;
    }
  }
}

// 16-bit PNGs keep the observed image as doubles and take two bytes a
// sample. The input is a TIFF: fssim's early estimate from a PNG header (a
// lower bound, which assumes 8-bit outputs) is then not made, and the
// estimate stated is the one made after decoding, with the outputs' depth.
TEST_P(MemoryEstimate, SixteenBitOutputsAreCounted) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's own memory would be measured";
  const int channels = GetParam();
  test::TempDir dir;
  const fs::path input = dir / "input.tif";
  const std::vector<std::uint8_t> tiff =
      encode_tiff_float(test::make_test_image(1600, 1000, channels));
  test::write_file(input, std::string(tiff.begin(), tiff.end()));
  for (const char* options : {"--png-depth 16", "--png-depth 16 --sheet --trials 3"}) {
    const std::string arguments =
        "-i " + input.string() + " -o " + (dir / "out").string() + " --threads 2 " + options;
    // Under a limit of the file's size, the decoding of the input is refused
    // first (a smaller limit refuses the file itself); just above that
    // decoding's memory, the run.
    const test::CommandResult decoding =
        test::run_fssim(arguments + " --max-memory " + std::to_string(tiff.size()));
    const double decoding_bytes = stated_bytes(decoding.err, "decoding it needs");
    ASSERT_GT(decoding_bytes, 0.0) << decoding.err;
    const double estimate = stated_estimate_bytes(arguments, decoding_bytes + 1048576.0);
    const double peak = peak_bytes(arguments + " --max-memory 0");
    ASSERT_GT(peak, 0.0) << arguments;
    std::printf(
        "memory estimate: %d channel(s), TIFF input %-33s estimate %7.1f MiB, peak %7.1f MiB\n",
        channels, options, estimate / 1048576.0, peak / 1048576.0);
    EXPECT_GE(estimate, peak) << arguments;
  }
}

// Aggregated noise with several trials keeps each row's recorded plan (M,
// V and its Knuth-branch pixels) for the later trials: counted too. The
// gray image is small enough to be planned, the RGB one is not.
TEST_P(MemoryEstimate, AggregatedNoisePlansAreCounted) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's own memory would be measured";
  const int channels = GetParam();
  test::TempDir dir;
  const fs::path input = dir / "input.png";
  const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(2048, 1000, channels));
  test::write_file(input, std::string(png.begin(), png.end()));
  for (const char* options : {"--trials 2", "--trials 3 --sheet"}) {
    const std::string arguments = "-i " + input.string() + " -o " + (dir / "out").string() +
                                  " --threads 2 --noise aggregated " + options;
    const double estimate = stated_estimate_bytes(arguments);
    const double peak = peak_bytes(arguments + " --max-memory 0");
    ASSERT_GT(peak, 0.0) << arguments;
    std::printf(
        "memory estimate: %d channel(s), aggregated %-20s estimate %7.1f MiB, peak %7.1f "
        "MiB\n",
        channels, options, estimate / 1048576.0, peak / 1048576.0);
    EXPECT_GE(estimate, peak) << arguments;
  }
}

INSTANTIATE_TEST_SUITE_P(GrayAndRgb, MemoryEstimate, ::testing::Values(1, 3));

// A refusal states what the run needs, rounded up: the same run under a
// limit of the stated size is not refused for memory again (the estimate
// from the PNG header is the one made after decoding: a palette decodes to
// RGB, a 16-bit input makes 16-bit outputs with --png-depth auto).
TEST(MemoryRefusal, StatedSizeIsEnough) {
  test::TempDir dir;
  test::PngSpec palette{640, 300, 8, PNG_COLOR_TYPE_PALETTE, false, {}, {}};
  for (int i = 0; i < 256; ++i) {
    palette.palette.push_back(
        {static_cast<png_byte>(i), static_cast<png_byte>(255 - i), static_cast<png_byte>(i / 2)});
  }
  test::PngSpec gray16{640, 300, 16, PNG_COLOR_TYPE_GRAY, false, {}, {}};
  for (int y = 0; y < 300; ++y) {
    palette.rows.emplace_back(640);
    gray16.rows.emplace_back(1280);
    for (int x = 0; x < 640; ++x) {
      palette.rows.back()[x] = static_cast<std::uint8_t>((x * 7 + y * 3) % 256);
      gray16.rows.back()[2 * x] = static_cast<std::uint8_t>((x + y) % 256);
      gray16.rows.back()[2 * x + 1] = static_cast<std::uint8_t>(x % 256);
    }
  }
  for (const auto& [name, spec] : {std::pair{"palette.png", &palette}, {"gray16.png", &gray16}}) {
    const std::vector<std::uint8_t> png = test::craft_png(*spec);
    test::write_file(dir / name, std::string(png.begin(), png.end()));
    for (const char* options : {"", "--png-depth auto", "--noise aggregated --trials 2"}) {
      const std::string arguments =
          "-i " + (dir / name).string() + " -o " + (dir / "out").string() + " " + options;
      const test::CommandResult refused = test::run_fssim(arguments + " --max-memory 1M");
      std::smatch m;
      ASSERT_TRUE(std::regex_search(refused.err, m, std::regex(R"(needs about ([0-9.]+ MiB))")))
          << arguments << ": " << refused.err;
      std::string size = m[1];
      size = size.substr(0, size.find(' ')) + "M";
      const test::CommandResult run = test::run_fssim(arguments + " --max-memory " + size);
      EXPECT_EQ(run.exit_code, 0) << arguments << " --max-memory " << size << ": " << run.err;
    }
  }
}

}  // namespace
}  // namespace fss
