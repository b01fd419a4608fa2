// End-to-end tests of TIFF input and of the exact outputs on the command
// line: an 8-bit TIFF simulates as the same PNG does, --save-float and
// --png-depth give the same bytes for any thread count, and a hostile TIFF
// or a memory limit too small for the float outputs is one line of error.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;

std::string camera() { return quote(test::source_path("data/camera.png")); }

// camera.png as an 8-bit gray TIFF, LZW-compressed, written with libtiff.
void write_camera_tiff(const fs::path& path) {
  const Image image = read_png(test::source_path("data/camera.png"));
  ASSERT_EQ(image.channels, 1);
  TIFF* tiff = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tiff, nullptr);
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(image.width));
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(image.height));
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(1));
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(8));
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, static_cast<std::uint16_t>(PHOTOMETRIC_MINISBLACK));
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, static_cast<std::uint16_t>(COMPRESSION_LZW));
  TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, static_cast<std::uint32_t>(16));
  std::vector<std::uint8_t> row(static_cast<std::size_t>(image.width));
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) row[x] = png8_sample(image.at(0, y, x));
    ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), static_cast<std::uint32_t>(y), 0), 1);
  }
  TIFFClose(tiff);
}

// Every file of `dir` with its bytes, report.json with `from` replaced by `to`.
std::vector<std::pair<std::string, std::string>> files_of(const fs::path& dir,
                                                          const std::string& from = "",
                                                          const std::string& to = "") {
  std::vector<std::pair<std::string, std::string>> files;
  for (const std::string& name : test::list_directory(dir)) {
    std::string bytes = test::read_file(dir / name);
    if (name == "report.json" && !from.empty()) {
      for (std::size_t at = bytes.find(from); at != std::string::npos;
           at = bytes.find(from, at + to.size())) {
        bytes.replace(at, from.size(), to);
      }
    }
    files.emplace_back(name, bytes);
  }
  return files;
}

// stdout without its last line ("Outputs: DIR").
std::string results(const std::string& out) { return out.substr(0, out.rfind("Outputs:")); }

TEST(TiffCli, AnEightBitTiffGivesTheSameOutputsAsThePng) {
  test::TempDir dir;
  write_camera_tiff(dir / "camera.tif");
  const auto from_png = run_fssim("--input " + camera() + " --outdir " + quote(dir / "png"));
  const auto from_tiff =
      run_fssim("--input " + quote(dir / "camera.tif") + " --outdir " + quote(dir / "tif"));
  ASSERT_EQ(from_png.exit_code, 0) << from_png.err;
  ASSERT_EQ(from_tiff.exit_code, 0) << from_tiff.err;
  EXPECT_EQ(results(from_tiff.out), results(from_png.out));
  EXPECT_EQ(from_tiff.err, "");
  const std::string png_path = test::source_path("data/camera.png").string();
  EXPECT_EQ(files_of(dir / "tif", (dir / "camera.tif").string(), png_path), files_of(dir / "png"));
}

TEST(TiffCli, FloatAndSixteenBitOutputsAreTheSameForAnyThreadCount) {
  test::TempDir dir;
  const std::string common =
      " --input " + camera() + " --save-float --png-depth 16 --sheet --no-plots --trials 2";
  const auto one = run_fssim(common + " --threads 1 --outdir " + quote(dir / "one"));
  const auto three = run_fssim(common + " --threads 3 --outdir " + quote(dir / "three"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(three.exit_code, 0) << three.err;
  const auto files = files_of(dir / "one");
  EXPECT_EQ(files, files_of(dir / "three"));
  int tifs = 0;
  for (const auto& [name, bytes] : files) tifs += name.ends_with(".tif") ? 1 : 0;
  EXPECT_EQ(tifs, 3);
}

TEST(TiffCli, PngDepthAutoFollowsTheInput) {
  test::TempDir dir;
  // A float TIFF input (more than 8 bits a sample): auto gives 16-bit PNGs.
  const std::vector<std::uint8_t> floats =
      encode_tiff_float(read_png(test::source_path("data/camera.png")));
  test::write_file(dir / "in.tif", std::string(floats.begin(), floats.end()));
  const auto deep = run_fssim("--input " + quote(dir / "in.tif") +
                              " --png-depth auto --no-plots --outdir " + quote(dir / "deep"));
  ASSERT_EQ(deep.exit_code, 0) << deep.err;
  EXPECT_EQ(static_cast<int>(test::read_file(dir / "deep/restored.png")[24]), 16);
  // An 8-bit input: auto gives today's bytes.
  const auto plain =
      run_fssim("--input " + camera() + " --no-plots --outdir " + quote(dir / "plain"));
  const auto autod = run_fssim("--input " + camera() + " --png-depth auto --no-plots --outdir " +
                               quote(dir / "auto"));
  ASSERT_EQ(autod.exit_code, 0) << autod.err;
  EXPECT_EQ(files_of(dir / "auto"), files_of(dir / "plain"));
  const auto bad =
      run_fssim("--input " + camera() + " --png-depth 12 --outdir " + quote(dir / "bad"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--png-depth"), std::string::npos) << bad.err;
}

TEST(TiffCli, AHostileTiffIsOneLineOfErrorAndNoOutput) {
  test::TempDir dir;
  const std::vector<std::uint8_t> good = encode_tiff_float(test::make_test_image(300, 6, 1, 4));
  const std::string cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2));
  test::write_file(dir / "cut.tif", cut);
  const auto result =
      run_fssim("--input " + quote(dir / "cut.tif") + " --outdir " + quote(dir / "out"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(test::lines_of(result.err).size(), 1U) << result.err;
  EXPECT_NE(result.err.find("cut.tif"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(TiffCli, TheMemoryLimitCountsTheFloatOutputs) {
  const Image image = read_png(test::source_path("data/camera.png"));
  const ShutterCode code = load_code("raskar");
  const Geometry g = Geometry::compute(image.width, code.length(), 1.0, 1.0);
  const std::size_t with_floats =
      estimate_working_memory_bytes(image.width, image.height, 1, g, 1, nullptr, 24);
  test::TempDir dir;
  const std::string limit = " --max-memory " + std::to_string(with_floats - 1);
  const auto plain = run_fssim("--input " + camera() + limit + " --outdir " + quote(dir / "a"));
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  const auto floats =
      run_fssim("--input " + camera() + limit + " --save-float --outdir " + quote(dir / "b"));
  EXPECT_EQ(floats.exit_code, 1);
  EXPECT_NE(floats.err.find("extra outputs (sheet, report, float or 16-bit)"), std::string::npos)
      << floats.err;
  EXPECT_NE(floats.err.find("--max-memory"), std::string::npos) << floats.err;
  EXPECT_FALSE(fs::exists(dir / "b"));
}

}  // namespace
}  // namespace fss
