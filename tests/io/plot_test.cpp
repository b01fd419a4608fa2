// Tests of the pictures (plot.h): valid PNGs of the requested size with drawn
// content, the elements each plot must show, figure sheets, determinism,
// thread safety and silence.
#include "fss/io/plot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Rgb = std::array<int, 3>;

// Colours of the plots' palette (plot_backend.cpp) that the tests look for.
constexpr Rgb kWhite = {255, 255, 255};
constexpr Rgb kCodeLine = {31, 92, 170};
constexpr Rgb kCodeFill = {196, 214, 238};
constexpr Rgb kReference = {90, 90, 90};
constexpr Rgb kMarker = {200, 30, 30};
constexpr Rgb kWarning = {190, 20, 20};

std::vector<double> gains_of(const char* name) { return builtin_code(name).value().gains; }

Image decode(const std::vector<std::uint8_t>& png) {
  return decode_png(png.data(), png.size(), "plot");
}

Rgb pixel(const Image& image, int x, int y) {
  if (image.channels == 1) {
    const int v = static_cast<int>(image.at(0, y, x));
    return {v, v, v};
  }
  return {static_cast<int>(image.at(0, y, x)), static_cast<int>(image.at(1, y, x)),
          static_cast<int>(image.at(2, y, x))};
}

int count_colour(const Image& image, const Rgb& colour) {
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) count += pixel(image, x, y) == colour;
  }
  return count;
}

// Rows [first, last] holding `colour`, if any.
std::optional<std::pair<int, int>> rows_with(const Image& image, const Rgb& colour) {
  std::optional<std::pair<int, int>> rows;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (pixel(image, x, y) != colour) continue;
      if (!rows) rows = std::make_pair(y, y);
      rows->second = y;
      break;
    }
  }
  return rows;
}

// A PNG of the given size, RGB, with a white page and drawn content covering
// a plausible part of it (not a blank page, not a flood).
void expect_drawn_plot(const std::vector<std::uint8_t>& png, int width, int height) {
  ASSERT_GE(png.size(), 8u);
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_TRUE(std::equal(signature, signature + 8, png.begin()));
  const Image image = decode(png);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  ASSERT_EQ(image.channels, 3);
  const int white = count_colour(image, kWhite);
  const double drawn = 1.0 - static_cast<double>(white) / (width * height);
  EXPECT_GT(drawn, 0.02) << "the plot is (nearly) blank";
  EXPECT_LT(drawn, 0.6) << "the plot is flooded";
  // The corners are page background.
  EXPECT_EQ(pixel(image, 0, 0), kWhite);
  EXPECT_EQ(pixel(image, width - 1, height - 1), kWhite);
}

// ---------------------------------------------------------------------------
// Curves

TEST(PlotCurves, IsAPngOfTheRequestedSizeWithDrawnContentAndGaps) {
  const std::vector<double> x = {0.25, 0.5, 0.75, 1.0, 1.25};
  const std::vector<CurveSeries> series = {
      {"measured", {1.4, 1.35, std::nan(""), 1.39, 1.8}, false, true},
      {"predicted", {1.41, 1.36, 1.34, 1.38, 1.79}, true, false}};
  expect_drawn_plot(plot_curves_png(x, series, "velocity", "RMSE"), kPlotWidth, kPlotHeight);
  expect_drawn_plot(plot_curves_png(x, series, "velocity", "RMSE", {400, 300, "title"}), 400, 300);
}

TEST(PlotCurves, RefusesBadInput) {
  const std::vector<double> x = {1.0, 2.0};
  EXPECT_TRUE(test::throws_error(
      [&] {
        plot_curves_png(x, {{"a", {1.0}, false, false}}, "x", "y");
      },
      ErrorKind::kUsage, {"curve 'a' has 1 values for 2 x values"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        plot_curves_png({2.0, 1.0}, {{"a", {1.0, 2.0}}}, "x", "y");
      },
      ErrorKind::kUsage, {"finite and increasing"}));
  EXPECT_TRUE(test::throws_error([&] { plot_curves_png(x, {}, "x", "y"); }, ErrorKind::kUsage,
                                 {"1 to 8 curves, got 0"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        plot_curves_png({}, {{"a", {}}}, "x", "y");
      },
      ErrorKind::kUsage, {"at least one x value"}));
}

// ---------------------------------------------------------------------------
// Code plot

TEST(PlotCode, IsAPngOfTheDefaultSizeWithDrawnContent) {
  expect_drawn_plot(plot_code_png(gains_of("raskar"), "raskar"), kPlotWidth, kPlotHeight);
  EXPECT_EQ(kPlotWidth, 640);
  EXPECT_EQ(kPlotHeight, 400);
}

TEST(PlotCode, HasTheRequestedSize) {
  expect_drawn_plot(plot_code_png(gains_of("mip"), "mip", {320, 240, ""}), 320, 240);
  expect_drawn_plot(plot_code_png(gains_of("mip"), "mip", {1000, 500, "title"}), 1000, 500);
}

TEST(PlotCode, DrawsTheStepsAndTheirArea) {
  const Image image = decode(plot_code_png(gains_of("raskar"), "raskar"));
  EXPECT_GT(count_colour(image, kCodeLine), 500);
  // raskar is half open: the area under the steps is a large part of the plot.
  EXPECT_GT(count_colour(image, kCodeFill), 20000);
}

TEST(PlotCode, NegativeGainsAreDrawnBelowTheZeroLine) {
  // Positive gains only: the area lies in the upper part of the plot, above
  // the zero line near the bottom.
  const Image positive = decode(plot_code_png({1.0, 0.5, 1.0, 0.5}, "positive"));
  const Image mixed = decode(plot_code_png({1.0, -1.0, 1.0, -1.0}, "mixed"));
  const auto positive_rows = rows_with(positive, kCodeFill);
  const auto mixed_rows = rows_with(mixed, kCodeFill);
  ASSERT_TRUE(positive_rows.has_value());
  ASSERT_TRUE(mixed_rows.has_value());
  const int bottom_of_plot = kPlotHeight - 58;  // the x axis
  EXPECT_LT(positive_rows->second, bottom_of_plot - 10);
  // With -1 gains the area reaches down to near the x axis.
  EXPECT_GT(mixed_rows->second, bottom_of_plot - 30);
  EXPECT_LT(mixed_rows->first, kPlotHeight / 3);
  // And the sign matters.
  EXPECT_NE(plot_code_png({1.0, -1.0}, "c"), plot_code_png({1.0, 1.0}, "c"));
}

TEST(PlotCode, BadArgumentsAreUsageErrors) {
  for (const PlotOptions& options : {PlotOptions{10, 400, ""}, PlotOptions{640, 100000, ""}}) {
    EXPECT_TRUE(test::throws_error([&] { plot_code_png({1.0}, "c", options); }, ErrorKind::kUsage,
                                   {"plot size"}));
  }
  EXPECT_TRUE(test::throws_error([] { plot_code_png({}, "empty"); }, ErrorKind::kUsage,
                                 {"code 'empty' has no gains"}));
  EXPECT_TRUE(test::throws_error(
      [] {
        plot_code_png({1.0, std::nan("")}, "nan");
      },
      ErrorKind::kUsage, {"code 'nan': gain", "is nan, gains must be finite"}));
}

// ---------------------------------------------------------------------------
// Spectrum plot

std::vector<std::uint8_t> spectrum(const char* name, double v = 1.0, double dt = 1.0,
                                   const PlotOptions& options = {}) {
  const std::vector<double> gains = gains_of(name);
  return plot_spectrum_png(gains, name, v, dt, analyze_kernel(gains, v, dt), options);
}

TEST(PlotSpectrum, IsAPngOfTheRequestedSizeWithDrawnContent) {
  expect_drawn_plot(spectrum("raskar"), kPlotWidth, kPlotHeight);
  expect_drawn_plot(spectrum("sinc", 0.7, 1.3, {800, 300, ""}), 800, 300);
}

TEST(PlotSpectrum, DrawsTheCurveTheDashedSnapshotAndTheMinimum) {
  const Image image = decode(spectrum("raskar"));
  EXPECT_GT(count_colour(image, kCodeLine), 1000);
  // The dashed line: many pixels, but interrupted — the reference colour
  // appears in several separate runs along a row near the snapshot's level.
  EXPECT_GT(count_colour(image, kReference), 100);
  EXPECT_GT(count_colour(image, kMarker), 60);  // two dots and the legend's
  EXPECT_EQ(count_colour(image, kWarning), 0);
}

TEST(PlotSpectrum, SaysWhenTheCodeIsNotInvertible) {
  const Image image = decode(spectrum("accumulation"));
  EXPECT_GT(count_colour(image, kWarning), 50);  // the red note
  EXPECT_GT(count_colour(image, kMarker), 30);
}

TEST(PlotSpectrum, DependsOnVelocity) {
  EXPECT_NE(spectrum("raskar", 1.0), spectrum("raskar", 0.5));
}

TEST(PlotSpectrum, SnapshotLineIsDashed) {
  // Sinc's |K| is flat near 0.85 and the snapshot's crosses it: look at the
  // row where the reference colour is most frequent and count its runs.
  const Image image = decode(spectrum("sinc"));
  int best_row = -1, best_count = 0;
  for (int y = 0; y < image.height; ++y) {
    int count = 0;
    for (int x = 0; x < image.width; ++x) count += pixel(image, x, y) == kReference;
    if (count > best_count) {
      best_count = count;
      best_row = y;
    }
  }
  ASSERT_GE(best_row, 0);
  int runs = 0;
  for (int x = 1; x < image.width; ++x) {
    runs += pixel(image, x, best_row) == kReference && pixel(image, x - 1, best_row) != kReference;
  }
  EXPECT_GE(runs, 5) << "row " << best_row;
}

// The axis is logarithmic, as in `fssim spectra`: raskar's peak of 26 does
// not flatten the snapshot's |K| (0.64 to 1) against the bottom of the plot.
// On a linear axis its dashed line would lie within 5 % of the plot area's
// height above the bottom edge; on the log axis from 0.1 it lies above 20 %.
TEST(PlotSpectrum, LogAxisKeepsTheSnapshotClearOfTheBottom) {
  const Image image = decode(spectrum("raskar"));
  const int top = 88, bottom = kPlotHeight - 58;  // the plot area (plot_code.cpp)
  double sum = 0.0;
  int count = 0;
  for (int y = top; y < bottom; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (pixel(image, x, y) == kReference) {
        sum += y;
        ++count;
      }
    }
  }
  ASSERT_GT(count, 100);
  const double height_above_bottom = (bottom - sum / count) / (bottom - top);
  EXPECT_GT(height_above_bottom, 0.2);
  EXPECT_LT(height_above_bottom, 0.6);
}

// A code without zeros whose |K| stays within one decade still gets a
// labelled decade below and above it, and a code with zeros is drawn with
// them at the bottom edge.
TEST(PlotSpectrum, FlatAndVanishingSpectraAreDrawn) {
  expect_drawn_plot(spectrum("sinc"), kPlotWidth, kPlotHeight);
  expect_drawn_plot(spectrum("snapshot", 0.5), kPlotWidth, kPlotHeight);
  expect_drawn_plot(spectrum("accumulation"), kPlotWidth, kPlotHeight);
}

// ---------------------------------------------------------------------------
// Overlay of spectra

std::vector<ShutterCode> paper_codes() {
  std::vector<ShutterCode> codes;
  for (const char* name : {"snapshot", "raskar", "random", "mip", "sinc"}) {
    codes.push_back(builtin_code(name).value());
  }
  return codes;
}

TEST(PlotSpectraOverlay, DrawsEveryCode) {
  const std::vector<std::uint8_t> png = plot_spectra_overlay_png(paper_codes(), 1.0, 1.0);
  expect_drawn_plot(png, kPlotWidth, kPlotHeight);
  const Image image = decode(png);
  // The series colours of raskar, random, mip and sinc (snapshot: dashed ink);
  // sinc's flat, antialiased line has the fewest pixels of exactly its colour.
  for (const Rgb& colour :
       {Rgb{31, 92, 170}, Rgb{214, 120, 20}, Rgb{40, 150, 60}, Rgb{150, 60, 170}}) {
    EXPECT_GT(count_colour(image, colour), 30) << colour[0] << "," << colour[1] << "," << colour[2];
  }
}

TEST(PlotSpectraOverlay, LinearAndLogDiffer) {
  const auto codes = paper_codes();
  expect_drawn_plot(plot_spectra_overlay_png(codes, 1.0, 1.0, false, {900, 450, ""}), 900, 450);
  EXPECT_NE(plot_spectra_overlay_png(codes, 1.0, 1.0, false),
            plot_spectra_overlay_png(codes, 1.0, 1.0, true));
}

TEST(PlotSpectraOverlay, ACodeWithZerosOnALogAxisIsDrawn) {
  std::vector<ShutterCode> codes = paper_codes();
  codes.push_back(builtin_code("accumulation").value());
  expect_drawn_plot(plot_spectra_overlay_png(codes, 1.0, 1.0, true), kPlotWidth, kPlotHeight);
}

TEST(PlotSpectraOverlay, TakesOneToEightCodes) {
  EXPECT_TRUE(test::throws_error([] { plot_spectra_overlay_png({}, 1.0, 1.0); }, ErrorKind::kUsage,
                                 {"1 to 8 codes, got 0"}));
  std::vector<ShutterCode> nine(9, builtin_code("raskar").value());
  EXPECT_TRUE(test::throws_error([&] { plot_spectra_overlay_png(nine, 1.0, 1.0); },
                                 ErrorKind::kUsage, {"1 to 8 codes, got 9"}));
  nine.pop_back();
  expect_drawn_plot(plot_spectra_overlay_png(nine, 1.0, 1.0), kPlotWidth, kPlotHeight);
}

// ---------------------------------------------------------------------------
// Figure sheets

TEST(FigureSheet, PanelsSitSideBySideUnderTheirCaptions) {
  const Image a = test::make_test_image(60, 40, 1, 1);
  const Image b = test::make_test_image(50, 40, 1, 2);
  const Image c = test::make_test_image(70, 40, 1, 3);
  const Image sheet =
      decode(figure_sheet_png({{&a, "first"}, {&b, "second"}, {&c, "third"}}, "a title"));
  ASSERT_EQ(sheet.width, kSheetMargin + 60 + kSheetMargin + 50 + kSheetMargin + 70 + kSheetMargin);
  ASSERT_EQ(sheet.height, kSheetHeaderHeight + 40 + kSheetMargin);
  ASSERT_EQ(sheet.channels, 1);  // gray in, gray out
  int left = kSheetMargin;
  for (const Image* panel : {&a, &b, &c}) {
    int differences = 0;
    for (int y = 0; y < 40; ++y) {
      for (int x = 0; x < panel->width; ++x) {
        differences += sheet.at(0, kSheetHeaderHeight + y, left + x) !=
                       std::clamp(std::round(panel->at(0, y, x)), 0.0, 255.0);
      }
    }
    EXPECT_EQ(differences, 0) << "panel at column " << left;
    // The gap after it is white.
    EXPECT_EQ(sheet.at(0, kSheetHeaderHeight + 20, left + panel->width), 255.0);
    left += panel->width + kSheetMargin;
  }
  // Text in the header.
  int dark = 0;
  for (int y = 0; y < kSheetHeaderHeight; ++y) {
    for (int x = 0; x < sheet.width; ++x) dark += sheet.at(0, y, x) < 128.0;
  }
  EXPECT_GT(dark, 100);
}

TEST(FigureSheet, ColourPanelsGiveAColourSheet) {
  const Image a = test::make_test_image(40, 30, 3, 1);
  const Image sheet = decode(figure_sheet_png({{&a, "x"}, {&a, "y"}}, "t"));
  EXPECT_EQ(sheet.channels, 3);
  EXPECT_EQ(sheet.at(2, kSheetHeaderHeight + 5, kSheetMargin + 7), std::round(a.at(2, 5, 7)));
}

TEST(FigureSheet, MismatchedPanelsAreRefused) {
  const Image gray = test::make_test_image(40, 30, 1, 1);
  const Image taller = test::make_test_image(40, 31, 1, 1);
  const Image colour = test::make_test_image(40, 30, 3, 1);
  for (const std::vector<SheetPanel>& panels :
       {std::vector<SheetPanel>{}, std::vector<SheetPanel>{{&gray, "a"}, {&taller, "b"}},
        std::vector<SheetPanel>{{&gray, "a"}, {&colour, "b"}},
        std::vector<SheetPanel>{{nullptr, "a"}}}) {
    EXPECT_TRUE(test::throws_error([&] { figure_sheet_png(panels, "t"); }, ErrorKind::kUsage,
                                   {"figure sheet"}));
  }
}

// A panel with a scale gets a gray bar under it, black to white from left
// to right, with its values below; the sheet grows by kSheetScaleHeight.
TEST(FigureSheet, AScaleIsAGrayBarUnderItsPanel) {
  const Image a = test::make_test_image(300, 40, 1, 1);
  const Image sheet = decode(figure_sheet_png(
      {{&a, "plain"}, {&a, "scaled", SheetScale{-10.0, 10.0, "gray levels"}}}, "t"));
  ASSERT_EQ(sheet.height, kSheetHeaderHeight + 40 + kSheetMargin + kSheetScaleHeight);
  const int bar_row = kSheetHeaderHeight + 40 + kSheetMargin + 10;
  const int panel_left = 2 * kSheetMargin + 300;
  // The longest non-decreasing run of gray along the bar's row, under the
  // second panel.
  int best_first = 0, best_length = 0, first = panel_left;
  for (int x = panel_left + 1; x < panel_left + 300; ++x) {
    if (sheet.at(0, bar_row, x) < sheet.at(0, bar_row, x - 1)) first = x;
    if (x - first + 1 > best_length) {
      best_length = x - first + 1;
      best_first = first;
    }
  }
  EXPECT_GE(best_length, 200);
  EXPECT_LE(sheet.at(0, bar_row, best_first + 2), 8.0);
  EXPECT_GE(sheet.at(0, bar_row, best_first + best_length - 3), 247.0);
  // Nothing under the first panel; the values and the unit under the second.
  int dark_first = 0, dark_second = 0;
  for (int y = kSheetHeaderHeight + 40 + kSheetMargin + 20; y < sheet.height; ++y) {
    for (int x = 0; x < 300; ++x) {
      dark_first += sheet.at(0, y, kSheetMargin + x) < 128.0;
      dark_second += sheet.at(0, y, panel_left + x) < 128.0;
    }
  }
  EXPECT_EQ(dark_first, 0);
  EXPECT_GT(dark_second, 100);
}

TEST(FigureSheet, AScaleNeedsTwoFiniteValues) {
  const Image a = test::make_test_image(60, 20, 1, 1);
  for (const SheetScale& scale : {SheetScale{1.0, 1.0, "u"}, SheetScale{0.0, std::nan(""), "u"},
                                  SheetScale{-HUGE_VAL, 1.0, "u"}}) {
    EXPECT_TRUE(test::throws_error(
        [&] {
          figure_sheet_png({{&a, "x", scale}}, "t");
        },
        ErrorKind::kUsage, {"scale", "finite, different values"}));
  }
}

// ---------------------------------------------------------------------------
// Behaviour of the renderer

TEST(Plots, AreDeterministic) {
  EXPECT_EQ(spectrum("mip"), spectrum("mip"));
  EXPECT_EQ(plot_code_png(gains_of("sinc"), "sinc"), plot_code_png(gains_of("sinc"), "sinc"));
}

TEST(Plots, UserTextIsDrawnLiterallyAndSilently) {
  // '#' is PLplot's escape character and invalid UTF-8 makes Pango complain:
  // neither may change the picture's frame or print anything.
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const auto with_hash = plot_code_png({1.0, 0.0, 1.0}, "code#d#u##\xff\xfe.txt");
  const auto with_title = plot_code_png({1.0, 0.0, 1.0}, "c", {640, 400, "#g \x80 <title>"});
  const Image panel = test::make_test_image(80, 20, 1, 1);
  const Image sheet =
      decode(figure_sheet_png({{&panel, "#u\xc3("}}, "##\xed\xa0\x80 a very long title"));
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
  expect_drawn_plot(with_hash, kPlotWidth, kPlotHeight);
  expect_drawn_plot(with_title, kPlotWidth, kPlotHeight);
  EXPECT_EQ(sheet.width, 2 * kSheetMargin + 80);
}

TEST(Plots, CanBeDrawnFromSeveralThreadsAtOnce) {
  const std::vector<std::uint8_t> code = plot_code_png(gains_of("random"), "random");
  const std::vector<std::uint8_t> spec = spectrum("raskar");
  std::vector<std::vector<std::uint8_t>> results(8);
  std::vector<std::thread> threads;
  threads.reserve(8);
  for (int i = 0; i < 8; ++i) {
    threads.emplace_back([&, i] {
      results[i] = i % 2 == 0 ? plot_code_png(gains_of("random"), "random") : spectrum("raskar");
    });
  }
  for (std::thread& t : threads) t.join();
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(results[i] == (i % 2 == 0 ? code : spec)) << i;
}

}  // namespace
}  // namespace fss
