// A campaign's images in every format the simulator reads (PNG; TIFF of 8- and 16-bit and float
// samples, either byte order): the rows of the same image, directories of both formats,
// refusals, bounded reads and change detection.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "campaign/user_input.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;

// A 120 x 24 gray crop of data/camera.png: narrow enough for a short code.
Image camera_crop() {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(120, 24, 1);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 240 + y, 200 + x);
  }
  return crop;
}

// `image` (integers 0..255) as an uncompressed gray TIFF of `bits` 8 or 16
// (a sample s stored as s or 257 s, which the simulator reads back as s),
// big-endian when `big_endian`.
void write_integer_tiff(const fs::path& path, const Image& image, int bits, bool big_endian) {
  TIFF* tiff = TIFFOpen(path.c_str(), big_endian ? "wb" : "wl");
  ASSERT_NE(tiff, nullptr);
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(image.width));
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(image.height));
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(bits));
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(1));
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, COMPRESSION_NONE);
  TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, static_cast<std::uint32_t>(image.height));
  std::vector<std::uint8_t> row8(image.width);
  std::vector<std::uint16_t> row16(image.width);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const auto s = static_cast<std::uint16_t>(image.at(0, y, x));
      row8[x] = static_cast<std::uint8_t>(s);
      row16[x] = static_cast<std::uint16_t>(s * 257);
    }
    void* row = bits == 8 ? static_cast<void*>(row8.data()) : static_cast<void*>(row16.data());
    ASSERT_EQ(TIFFWriteScanline(tiff, row, static_cast<std::uint32_t>(y), 0), 1);
  }
  TIFFClose(tiff);
}

void write_png(const fs::path& path, const Image& image) {
  const auto png = encode_png8(image);
  test::write_file(path, std::string(png.begin(), png.end()));
}

void write_float_tiff(const fs::path& path, const Image& image) {
  const auto tiff = encode_tiff_float(image);
  test::write_file(path, std::string(tiff.begin(), tiff.end()));
}

CampaignSpec spec_of(const std::vector<std::string>& inputs, const fs::path& dir) {
  test::write_file(dir / "short.txt", "1 0 1 1 0 0 1 1\n");
  CampaignSpec spec;
  spec.inputs = inputs;
  spec.codes = {(dir / "short.txt").string()};
  spec.velocity = "0.5,1";
  spec.snr = "50,200";
  spec.trials = 2;
  spec.seed = 3;
  return spec;
}

std::size_t column(const char* name) {
  const auto& columns = campaign_columns();
  const auto it = std::find_if(columns.begin(), columns.end(),
                               [&](const ResultColumn& c) { return std::string(c.name) == name; });
  EXPECT_NE(it, columns.end()) << name;
  return static_cast<std::size_t>(it - columns.begin());
}

// Each TIFF of the crop runs to the rows of the crop itself (the pixels the
// PNG holds) under the TIFF campaign's seeds, and to the PNG campaign's
// numbers in every column that does not depend on the seed.
TEST(CampaignImageFormats, TiffRowsAreThoseOfTheSameImageInPng) {
  test::TempDir tmp;
  const Image crop = camera_crop();
  write_png(tmp / "crop.png", crop);
  const Image png_image = read_png(tmp / "crop.png");
  write_integer_tiff(tmp / "crop8.tif", crop, 8, false);
  write_integer_tiff(tmp / "crop16.tiff", crop, 16, true);
  write_float_tiff(tmp / "cropf.TIF", crop);
  const ResolvedCampaign png = resolve_campaign(spec_of({(tmp / "crop.png").string()}, tmp.path()));
  const std::vector<ResultRow> png_rows = RunCampaign(png, (tmp / "png").string(), {}).rows;
  ASSERT_EQ(png_rows.size(), 4U);
  for (const char* name : {"crop8.tif", "crop16.tiff", "cropf.TIF"}) {
    SCOPED_TRACE(name);
    const ResolvedCampaign c = resolve_campaign(spec_of({(tmp / name).string()}, tmp.path()));
    const std::vector<ResultRow> rows = RunCampaign(c, (tmp / "out").string(), {}).rows;
    fs::remove_all(tmp / "out");
    ASSERT_EQ(rows.size(), png_rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i], run_setting(c, setting_at(c, static_cast<long long>(i)), png_image, {}));
      EXPECT_EQ(rows[i][column("status")], "ok");
      for (const char* exact : {"blur_length", "predicted_rmse", "predicted_rmse_noise_free",
                                "predicted_sigma", "snr_level100", "status"}) {
        EXPECT_EQ(rows[i][column(exact)], png_rows[i][column(exact)]) << exact << " row " << i;
      }
    }
  }
}

std::vector<std::string> image_names(const ResolvedCampaign& c) {
  std::vector<std::string> names;
  for (const CampaignImage& image : c.images) names.push_back(fs::path(image.name).filename());
  return names;
}

// A directory stands for its *.png, *.tif and *.tiff files in any case,
// sorted; hidden files and files that are no image are left out; an image
// of a format the simulator does not read is refused by name.
TEST(CampaignImageFormats, DirectoriesTakeEveryFormatTheSimulatorReads) {
  test::TempDir tmp;
  const Image crop = camera_crop();
  fs::create_directories(tmp / "images");
  write_png(tmp / "images" / "b.png", crop);
  write_integer_tiff(tmp / "images" / "a.TIF", crop, 8, false);
  write_float_tiff(tmp / "images" / "c.tiff", crop);
  write_png(tmp / "images" / "d.PNG", crop);
  test::write_file(tmp / "images" / "notes.txt", "not an image");
  test::write_file(tmp / "images" / ".e.png", "a hidden file, not an image");
  const ResolvedCampaign c = resolve_campaign(spec_of({(tmp / "images").string()}, tmp.path()));
  EXPECT_EQ(image_names(c), std::vector<std::string>({"a.TIF", "b.png", "c.tiff", "d.PNG"}));
  // The two formats hold the same pixels, in different bytes.
  EXPECT_NE(c.images[0].sha256, c.images[1].sha256);
  const CampaignRunSummary run = RunCampaign(c, (tmp / "out").string(), {});
  EXPECT_EQ(run.rows.size(), 4U * 4U);

  test::write_file(tmp / "images" / "f.JPG", "\xff\xd8\xff");
  EXPECT_TRUE(test::throws_error(
      [&] { resolve_campaign(spec_of({(tmp / "images").string()}, tmp.path())); },
      ErrorKind::kUsage, {"f.JPG", "PNG and TIFF only"}));
  fs::create_directories(tmp / "empty");
  test::write_file(tmp / "empty" / "notes.txt", "not an image");
  EXPECT_TRUE(
      test::throws_error([&] { resolve_campaign(spec_of({(tmp / "empty").string()}, tmp.path())); },
                         ErrorKind::kUsage, {"matches no PNG or TIFF file"}));
}

// The content decides, not the name: a TIFF named .png runs, a .tif that is
// neither format is refused naming the file; reads are bounded; a TIFF
// changed after the campaign started is refused at its run.
TEST(CampaignImageFormats, SignaturesBoundsAndChanges) {
  test::TempDir tmp;
  const Image crop = camera_crop();
  write_integer_tiff(tmp / "tiff.png", crop, 8, false);
  EXPECT_EQ(resolve_campaign(spec_of({(tmp / "tiff.png").string()}, tmp.path())).images.size(), 1U);
  test::write_file(tmp / "text.tif", "GIF89a, not a TIFF");
  EXPECT_TRUE(test::throws_error(
      [&] { resolve_campaign(spec_of({(tmp / "text.tif").string()}, tmp.path())); },
      ErrorKind::kRuntime, {"text.tif", "is not a PNG or TIFF file"}));
  EXPECT_TRUE(test::throws_error(
      [&] { campaign_input::read_image_file((tmp / "tiff.png").string(), 100, "image"); },
      ErrorKind::kRuntime, {"tiff.png", "larger than"}));
  // An endless stream is refused by its first bytes.
  EXPECT_TRUE(test::throws_error(
      [&] { campaign_input::read_image_file("/dev/zero", std::size_t{1} << 30, "image"); },
      ErrorKind::kRuntime, {"/dev/zero", "is not a PNG or TIFF file"}));

  write_integer_tiff(tmp / "crop.tif", crop, 16, false);
  const ResolvedCampaign c = resolve_campaign(spec_of({(tmp / "crop.tif").string()}, tmp.path()));
  Image brighter = crop;
  brighter.at(0, 0, 0) = 255 - crop.at(0, 0, 0);
  write_integer_tiff(tmp / "crop.tif", brighter, 16, false);
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "out").string(), {}); },
                                 ErrorKind::kRuntime, {"changed since the campaign started"}));
}

}  // namespace
}  // namespace fss
