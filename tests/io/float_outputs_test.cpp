// Tests of the exact outputs of a run (outputs.h): observed.tif, restored.tif
// and residual.tif hold the report's values as floats, unclamped and not
// stretched; 16-bit image PNGs; the memory they need is counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/outputs.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/memory_estimate.h"
#include "io/observed_png8.h"
#include "io/write_run.h"
#include "support/test_util.h"

namespace fss {
namespace {

// An image with sharp edges between black and white: a code with negative
// gains gives negative observations and restorations beyond [0, 255].
Image edges_input(int channels) {
  Image image = test::make_test_image(96, 6, channels, 11);
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        if ((x / 9 + y + c) % 2 == 0) image.at(c, y, x) = x % 18 < 9 ? 0.0 : 255.0;
      }
    }
  }
  return image;
}

SimulationReport run(const Image& input, const std::vector<double>& gains) {
  SimulationOptions options;
  options.seed = 5;
  options.threads = 1;
  return Simulate(options, input, ShutterCode{"signed", gains});
}

Image read_output(const test::TempDir& dir, const std::string& name) {
  const std::string bytes = test::read_file(dir / ("out/" + name));
  const std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
  if (name.ends_with(".tif")) return decode_tiff(data.data(), data.size(), name);
  return decode_png(data.data(), data.size(), name);
}

OutputOptions float_options() {
  OutputOptions options;
  options.plots = false;
  options.float_outputs = true;
  return options;
}

// Each value of `image` must be the nearest float of want(c, y, x).
template <typename F>
void expect_floats_of(const Image& image, int width, int height, int channels, F&& want) {
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  ASSERT_EQ(image.channels, channels);
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        ASSERT_EQ(image.at(c, y, x), static_cast<double>(static_cast<float>(want(c, y, x))))
            << c << " " << y << " " << x;
      }
    }
  }
}

TEST(FloatOutputs, HoldTheReportsValuesUnclampedAndTheResidualUnstretched) {
  for (const int channels : {1, 3}) {
    const Image input = edges_input(channels);
    const SimulationReport report = run(input, {1.0, -0.9, 1.0, 0.8, -0.7, 1.0});
    const auto [low, high] =
        std::minmax_element(report.observed.data.begin(), report.observed.data.end());
    ASSERT_LT(*low, 0.0) << "the test needs negative observations";
    ASSERT_GT(*high, 255.0);
    test::TempDir dir;
    write_outputs(dir / "out", report, input, "in.png", float_options());
    const int wo = report.restored.width, h = report.height, off = report.output_first_column();
    expect_floats_of(read_output(dir, "observed.tif"), wo, h, channels,
                     [&](int c, int y, int x) { return report.observed.at(c, y, x); });
    expect_floats_of(read_output(dir, "restored.tif"), wo, h, channels,
                     [&](int c, int y, int x) { return report.restored.at(c, y, x); });
    // residual = groundtruth - restored, exactly (then rounded to a float once)
    expect_floats_of(read_output(dir, "residual.tif"), wo, h, channels, [&](int c, int y, int x) {
      return input.at(c, y, x + off) - report.restored.at(c, y, x);
    });
    // The PNGs of the same name: same crop, rounded and clamped.
    const Image observed_png = read_output(dir, "observed.png");
    const Image observed_tif = read_output(dir, "observed.tif");
    ASSERT_EQ(observed_png.data.size(), observed_tif.data.size());
    for (std::size_t i = 0; i < observed_png.data.size(); ++i) {
      ASSERT_EQ(observed_png.data[i], png8_sample(report.observed.data[i])) << i;
    }
  }
}

TEST(FloatOutputs, AreNotWrittenByDefaultAndNeedTheObservedDoubles) {
  const Image input = edges_input(1);
  SimulationOptions options;
  options.threads = 1;
  ObservedPng8 rows(input.height, 1);
  const SimulationReport report = Simulate(options, input, ShutterCode{"c", {1, 0, 1, 1}}, &rows);
  test::TempDir dir;
  OutputOptions plain;
  plain.plots = false;
  write_outputs(dir / "out", report, rows, input, "in.png", plain);
  const std::vector<std::string> names = test::list_directory(dir / "out");
  EXPECT_EQ(std::count_if(names.begin(), names.end(),
                          [](const std::string& n) { return n.ends_with(".tif"); }),
            0);
  EXPECT_TRUE(test::throws_error(
      [&] { write_outputs(dir / "floats", report, rows, input, "in.png", float_options()); },
      ErrorKind::kUsage, {"observed.tif", "observed image"}));
  OutputOptions sixteen = plain;
  sixteen.image_depth = PngDepth::k16;
  EXPECT_TRUE(test::throws_error(
      [&] { write_outputs(dir / "sixteen", report, rows, input, "in.png", sixteen); },
      ErrorKind::kUsage, {"observed.png", "16-bit"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "floats"));
  EXPECT_FALSE(std::filesystem::exists(dir / "sixteen"));
}

TEST(SixteenBitOutputs, TheFourImagePngsHoldTheValuesAt16Bits) {
  const Image input = edges_input(3);
  const SimulationReport report = run(input, {1.0, 0.0, 1.0, 1.0});
  test::TempDir dir;
  OutputOptions options;
  options.plots = false;
  options.sheet = true;
  options.image_depth = PngDepth::k16;
  write_outputs(dir / "out", report, input, "in.png", options);
  const auto depth_of = [&](const std::string& name) {
    return static_cast<int>(static_cast<std::uint8_t>(test::read_file(dir / ("out/" + name))[24]));
  };
  for (const char* name : {"observed.png", "restored.png", "groundtruth.png", "residual.png"}) {
    EXPECT_EQ(depth_of(name), 16) << name;
  }
  EXPECT_EQ(depth_of("sheet.png"), 8);
  const Image restored = read_output(dir, "restored.png");
  ASSERT_EQ(restored.data.size(), report.restored.data.size());
  for (std::size_t i = 0; i < restored.data.size(); ++i) {
    ASSERT_EQ(restored.data[i], png16_sample(report.restored.data[i]) / 257.0) << i;
  }
  // The ground truth of an 8-bit input is its gray levels exactly: g -> 257 g.
  const Image truth = read_output(dir, "groundtruth.png");
  const Image expected = groundtruth_image(input, report);
  for (std::size_t i = 0; i < truth.data.size(); ++i) {
    ASSERT_EQ(truth.data[i], png16_sample(expected.data[i]) / 257.0) << i;
  }
}

TEST(OutputsMemory, FloatAnd16BitOutputsAreCountedInTheLimit) {
  // Large enough for the encoding buffers to outweigh the RMSE_CI scratch.
  const Image input(1000, 200, 3, 10.0);
  const ShutterCode code{"c", {1, 0, 1, 1}};
  SimulationOptions simulation;
  simulation.threads = 1;
  const Geometry g = Geometry::compute(input.width, code.length(), 1.0, 1.0);
  OutputOptions floats;
  floats.float_outputs = true;
  EXPECT_EQ(output_encoding_bytes_per_sample(OutputOptions{}), 0U);
  EXPECT_EQ(output_encoding_bytes_per_sample(floats), 24U);
  const std::size_t plain = estimate_working_memory_bytes(input.width, input.height, 3, g, 1);
  const std::size_t with_floats =
      estimate_working_memory_bytes(input.width, input.height, 3, g, 1, nullptr, 24);
  ASSERT_GT(with_floats, plain);
  // The one check every interface makes, with the outputs' bytes counted.
  const ImageShape shape{input.width, input.height, input.channels};
  const std::size_t run_plain = estimate_run_memory_bytes(shape, simulation, code, false, 0);
  const std::size_t run_floats = estimate_run_memory_bytes(shape, simulation, code, false, 24);
  EXPECT_EQ(run_floats - run_plain, with_floats - plain);
  const auto check = [&](std::size_t extra) {
    check_run_memory(shape, simulation, code, false, extra, "this run");
  };
  simulation.max_memory_bytes = run_plain;  // enough for Simulate, not for the TIFFs
  EXPECT_NO_THROW(check(0));
  EXPECT_TRUE(test::throws_error([&] { check(24); }, ErrorKind::kLimit,
                                 {"this run needs about", "memory limit"}));
  simulation.max_memory_bytes = run_floats;
  EXPECT_NO_THROW(check(24));
  simulation.max_memory_bytes = 0;  // no limit
  EXPECT_NO_THROW(check(24));
}

}  // namespace
}  // namespace fss
