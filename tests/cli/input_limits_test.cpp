// The input image is read once and within the memory limit: a pipe or a
// FIFO gives the same run as the file; a file larger than --max-memory is
// refused before it is read, a stream once it has given that much, each
// with one line naming the input and the limit.
#include <sys/stat.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;

class InputLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    const Image image = test::make_test_image(900, 16, 1);
    const std::vector<std::uint8_t> png = encode_png8(image);
    test::write_file(png_, std::string(png.begin(), png.end()));
    const std::vector<std::uint8_t> tiff = encode_tiff_float(image);
    test::write_file(tiff_, std::string(tiff.begin(), tiff.end()));
  }

  // fssim's standard output for `input` (a shell word) into a fresh folder.
  CommandResult run(const std::string& input, const std::string& options = "") const {
    fs::remove_all(dir_ / "out");
    return test::run_fssim("-i " + input + " --no-plots -o " + quote(dir_ / "out") + " " + options);
  }

  test::TempDir dir_;
  fs::path png_ = dir_ / "in.png";
  fs::path tiff_ = dir_ / "in.tif";
};

// The standard output without its last line ("Outputs: ...", the same folder).
std::string results_of(const CommandResult& r) {
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out;
}

TEST_F(InputLimits, PipeAndFifoAreReadOnce) {
  for (const fs::path& file : {png_, tiff_}) {
    const std::string expected = results_of(run(quote(file)));
    const std::string restored = test::read_file(dir_ / "out" / "restored.png");
    // cat FILE | fssim -i /dev/stdin
    const CommandResult piped =
        test::run_command("{ cat " + quote(file) + " | '" + FSSIM_BINARY_PATH +
                          "' -i /dev/stdin --no-plots -o " + quote(dir_ / "piped") + "; }");
    EXPECT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_EQ(piped.out.substr(0, piped.out.rfind("Outputs:")),
              expected.substr(0, expected.rfind("Outputs:")));
    EXPECT_EQ(test::read_file(dir_ / "piped" / "restored.png"), restored);
    // a FIFO
    const fs::path fifo = dir_ / "fifo";
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const CommandResult fed = test::run_command(
        "{ cat " + quote(file) + " > " + quote(fifo) + " & } ; '" + FSSIM_BINARY_PATH + "' -i " +
        quote(fifo) + " --no-plots -o " + quote(dir_ / "fifo-out"));
    EXPECT_EQ(fed.exit_code, 0) << fed.err;
    EXPECT_EQ(test::read_file(dir_ / "fifo-out" / "restored.png"), restored);
  }
}

// A valid image followed by 96 MiB of padding, under a 64 MiB limit: refused
// from its size, without reading it.
TEST_F(InputLimits, FileOverTheLimitIsRefusedBeforeReading) {
  for (const fs::path& file : {png_, tiff_}) {
    const fs::path padded = dir_ / ("padded" + file.extension().string());
    fs::copy_file(file, padded, fs::copy_options::overwrite_existing);
    fs::resize_file(padded, fs::file_size(file) + (std::size_t{96} << 20));
    const CommandResult r = run(quote(padded), "--max-memory 64M");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err, "fssim: error: input '" + padded.string() +
                         "' is 96.1 MiB, more than the memory limit of 64.0 MiB (raise it with "
                         "--max-memory)\n");
    EXPECT_FALSE(fs::exists(dir_ / "out"));
  }
}

// The same padding through a pipe: refused once 64 MiB were read.
TEST_F(InputLimits, StreamOverTheLimitIsRefusedAtTheLimit) {
  const CommandResult r = test::run_command(
      "{ { cat " + quote(png_) + "; head -c 100663296 /dev/zero; } | '" + FSSIM_BINARY_PATH +
      "' -i /dev/stdin --no-plots --max-memory 64M -o " + quote(dir_ / "out") + "; }");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err,
            "fssim: error: input '/dev/stdin' holds more than the memory limit of 64.0 MiB (raise "
            "it with --max-memory)\n");
}

}  // namespace
}  // namespace fss
