// Tests of the figures of measurements against their prediction (plot.h,
// plot_measured_png/svg) and of their layout (src/io/plot_layout.h): ticks of
// log axes, titles that fit, the legend clear of the data and only for
// series with data, and the PNG's ink within the layout's estimates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "io/plot_layout.h"
#include "support/test_util.h"

namespace fss {
namespace {

using plotting::layout_measured;
using plotting::LegendMark;
using plotting::MeasuredLayout;
using plotting::Rect;
using plotting::Tick;

const double kNan = std::nan("");

std::vector<std::string> labels_of(const std::vector<Tick>& ticks) {
  std::vector<std::string> labels;
  for (const Tick& t : ticks) {
    if (!t.label.empty())
      labels.push_back(t.exponent.empty() ? t.label : t.label + "^" + t.exponent);
  }
  return labels;
}

// A figure of two series over snr 25 .. 400: RMSE falling as 1 / snr.
MeasuredFigure falling_figure() {
  MeasuredFigure f;
  f.x = {25, 50, 100, 200, 400};
  for (const double scale : {1.0, 1.6}) {
    MeasuredSeries s;
    s.name = scale == 1.0 ? "snapshot" : "raskar";
    for (const double x : f.x) {
      s.measured.push_back(scale * 190.0 / x);
      s.error.push_back(0.02 * scale * 190.0 / x);
      s.predicted.push_back(scale * 188.0 / x);
    }
    f.series.push_back(s);
  }
  f.x_label = "snr";
  f.y_label = "RMSE (gray levels)";
  f.log_x = true;
  return f;
}

bool overlaps(const Rect& a, const Rect& b) {
  return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
}

void expect_legend_clear(const MeasuredFigure& f, const MeasuredLayout& l) {
  for (const Rect& m : plotting::data_marks(f, l)) {
    EXPECT_FALSE(overlaps(m, l.legend.box))
        << "a mark at " << m.left << "," << m.top << " under the legend";
  }
}

TEST(MeasuredPlotLayout, LogAxesLabelEveryDecade) {
  EXPECT_EQ(labels_of(plotting::log_ticks(0.5, 2000)),
            (std::vector<std::string>{"1", "10", "100", "1000"}));
  // Less than two decades: 2 and 5 times the powers too, at least 3 labels.
  EXPECT_EQ(labels_of(plotting::log_ticks(22, 450)),
            (std::vector<std::string>{"50", "100", "200"}));
  EXPECT_EQ(labels_of(plotting::log_ticks(0.3, 9)),
            (std::vector<std::string>{"0.5", "1", "2", "5"}));
  // Beyond 0.001 .. 90000: powers of ten.
  EXPECT_EQ(labels_of(plotting::log_ticks(2e-6, 3e-3)),
            (std::vector<std::string>{"10^-5", "10^-4", "0.001"}));
  EXPECT_EQ(labels_of(plotting::log_ticks(5e3, 2e7)),
            (std::vector<std::string>{"10000", "10^5", "10^6", "10^7"}));
  // Less than a factor 3: plain steps.
  EXPECT_GE(labels_of(plotting::log_ticks(97, 206)).size(), 3u);
  for (const auto& [low, high] : {std::pair{1.01, 1.09}, {3e-7, 4e-7}, {0.9, 1.1e9}}) {
    const std::vector<Tick> ticks = plotting::log_ticks(low, high);
    EXPECT_GE(labels_of(ticks).size(), 3u) << low << ".." << high;
    for (const Tick& t : ticks) EXPECT_TRUE(t.value >= low * 0.999 && t.value <= high * 1.001);
  }
}

TEST(MeasuredPlotLayout, TitlesFitTheirPicture) {
  const std::string name(120, 'x');
  for (const std::string& title :
       {std::string("RMSE vs snr: camera.png, numerical, v 0.5, dt 1; 10 trials, margin 100"),
        "RMSE vs snr: " + name +
            ".png, numerical, v 0.5, restore velocity 0.5, dt 1, read noise 3; "
            "10 trials, margin auto",
        name + name + name}) {
    for (const int width : {kPlotMinSide, 640, 800}) {
      const plotting::TextBlock block = plotting::fit_text(title, width - 16.0, 15.0, 10.0);
      ASSERT_FALSE(block.lines.empty());
      EXPECT_LE(block.lines.size(), 2u);
      EXPECT_GE(block.size, 10.0);
      for (const std::string& line : block.lines) {
        EXPECT_LE(plotting::text_width(line, block.size), width - 16.0) << line;
      }
    }
  }
  // A title that fits stays whole at the full size; a longer one is cut only past two lines.
  EXPECT_EQ(plotting::fit_text("short", 600, 15, 10).lines, std::vector<std::string>{"short"});
  const plotting::TextBlock two =
      plotting::fit_text(std::string(60, 'a') + "; " + std::string(60, 'b'), 784, 15, 10);
  EXPECT_EQ(two.lines,
            (std::vector<std::string>{std::string(60, 'a') + ";", std::string(60, 'b')}));
  const plotting::TextBlock cut = plotting::fit_text(name + name + name, 784, 15, 10);
  EXPECT_NE(cut.lines.back().find("…"), std::string::npos);
}

TEST(MeasuredPlotLayout, LegendKeepsClearOfTheData) {
  MeasuredFigure falling = falling_figure();
  const MeasuredLayout l = layout_measured(falling, "title", 800, 500);
  EXPECT_TRUE(l.legend.inside);
  expect_legend_clear(falling, l);
  // Rising data: the legend moves; data in every corner: it goes right of the plot area.
  MeasuredFigure rising = falling;
  for (MeasuredSeries& s : rising.series) std::reverse(s.measured.begin(), s.measured.end());
  expect_legend_clear(rising, layout_measured(rising, "title", 800, 500));
  MeasuredFigure everywhere = falling;
  everywhere.log_x = false;
  everywhere.x = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  everywhere.series = {{"a", {1, 9, 1, 9, 1, 9, 1, 9, 1}, {}, {}, {}, -1},
                       {"b", {9, 1, 9, 1, 9, 1, 9, 1, 9}, {}, {}, {}, -1}};
  const MeasuredLayout outside = layout_measured(everywhere, "title", 800, 500);
  EXPECT_FALSE(outside.legend.inside);
  EXPECT_GT(outside.legend.box.left, outside.plot.right);
  EXPECT_LE(outside.legend.box.right, 800);
  expect_legend_clear(everywhere, outside);
  // A wide legend goes under the plot area, in columns, within the picture.
  for (MeasuredSeries& s : everywhere.series) s.name += ": wiener (power-law prior, gamma 1.5)";
  const MeasuredLayout below = layout_measured(everywhere, "title", 800, 500);
  EXPECT_FALSE(below.legend.inside);
  EXPECT_GT(below.legend.box.top, below.x_label_y);
  EXPECT_LT(below.legend.box.bottom, below.key.front().y - 9.0);
  EXPECT_GE(below.legend.box.left, 0.0);
  EXPECT_LE(below.legend.box.right, 800.0);
  EXPECT_GT(below.plot.width(), 600.0);
}

TEST(MeasuredPlotLayout, LegendListsOnlySeriesWithData) {
  MeasuredFigure f = falling_figure();
  f.series.push_back({"accumulation", std::vector<double>(5, kNan), {}, {}, {}, 5});
  f.open_key = "RMSE margin < 3B";
  const MeasuredLayout l = layout_measured(f, "title", 800, 500);
  std::vector<std::string> series;
  for (const plotting::LegendRow& row : l.legend.rows) {
    if (row.mark == LegendMark::kSeries) series.push_back(row.text);
  }
  EXPECT_EQ(series, (std::vector<std::string>{"snapshot", "raskar"}));
  EXPECT_EQ(l.legend.rows.size(), 2u);
  // The key under the plot: points and the predicted line; no open marker without an open point.
  ASSERT_EQ(l.key.size(), 2u);
  EXPECT_EQ(l.key[0].row.mark, LegendMark::kPoints);
  EXPECT_TRUE(l.key[0].row.has_bar);
  EXPECT_EQ(l.key[1].row.mark, LegendMark::kPredicted);
  EXPECT_GT(l.key[0].y, l.plot.bottom);
  f.series[0].open = {true, false, false, false, false};
  EXPECT_EQ(layout_measured(f, "title", 800, 500).key.back().row.mark, LegendMark::kOpen);
  // Colours follow the series' own, not their place.
  EXPECT_EQ(l.colours, (std::vector<int>{0, 1, 5}));
}

TEST(MeasuredPlotLayout, ValuesOverADecadeGetALogAxisAndOthersStartAtZero) {
  EXPECT_TRUE(layout_measured(falling_figure(), "t", 800, 500).y.log);
  MeasuredFigure flat = falling_figure();
  for (MeasuredSeries& s : flat.series) {
    s.measured = {2, 2.2, 2.4, 2.6, 2.8};
    s.predicted.clear();
  }
  const MeasuredLayout l = layout_measured(flat, "t", 800, 500);
  EXPECT_FALSE(l.y.log);
  EXPECT_EQ(l.y.low, 0.0);
  EXPECT_GE(l.y.high, 2.8 + 2 * 0.056);  // room above the top bar
}

// One x value: an axis around it with 3 labels at least, the prediction a dash beside the point.
TEST(MeasuredPlotLayout, OneXValue) {
  MeasuredFigure f;
  f.x = {100};
  f.series = {{"raskar", {2.0}, {0.1}, {2.1}, {}, -1}};
  f.log_x = true;
  const MeasuredLayout l = layout_measured(f, "t", 640, 400);
  EXPECT_GE(labels_of(l.x.ticks).size(), 3u);
  EXPECT_LT(l.x.low, 100.0);
  EXPECT_GT(l.x.high, 100.0);
  const auto runs = plotting::predicted_runs(f, l, 0);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0], std::vector<std::size_t>{0});
  const double x = l.x.pixel(100.0);
  const std::vector<Rect> marks = plotting::data_marks(f, l);
  EXPECT_TRUE(std::any_of(marks.begin(), marks.end(), [&](const Rect& m) {
    return m.left <= x - plotting::kPredictedDash && m.right >= x + plotting::kPredictedDash;
  }));
  EXPECT_NE(plot_measured_svg(f, {640, 400, "t"}).find("<polyline"), std::string::npos);
}

// The PNG's title ink lies within the layout's estimate of its width, centred: text that fits
// by the estimate is not clipped.
TEST(MeasuredPlot, PngTitleInkFitsTheEstimate) {
  const std::string title = "RMSE vs snr: " + std::string(70, 'W') + ".png, numerical, v 0.5";
  MeasuredFigure f = falling_figure();
  const PlotOptions options{640, 400, title};
  const MeasuredLayout l = layout_measured(f, title, 640, 400);
  ASSERT_EQ(l.title.lines.size(), 2u);
  const Image image = [&] {
    const std::vector<std::uint8_t> png = plot_measured_png(f, options);
    return decode_png(png.data(), png.size(), "plot");
  }();
  const int bottom = static_cast<int>(l.title_top + l.title.height());
  int left = image.width, right = -1;
  for (int y = 0; y < bottom; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (image.at(0, y, x) < 200) left = std::min(left, x), right = std::max(right, x);
    }
  }
  double widest = 0.0;
  for (const std::string& line : l.title.lines)
    widest = std::max(widest, plotting::text_width(line, l.title.size));
  ASSERT_GT(right, left);
  EXPECT_GE(left, l.title_x - widest / 2 - 1);
  EXPECT_LE(right, l.title_x + widest / 2 + 1);
  EXPECT_GE(left, 8);
  EXPECT_LE(right, 640 - 8);
  EXPECT_GT(right - left, 0.85 * widest);  // the estimate is not far above the ink either
}

TEST(MeasuredPlot, PngAndSvgOfOneLayout) {
  MeasuredFigure f = falling_figure();
  f.notes = {"no data: accumulation (not-invertible)"};
  const PlotOptions options{800, 500, "RMSE vs snr: camera.png & <b>"};
  const std::vector<std::uint8_t> png = plot_measured_png(f, options);
  const Image image = decode_png(png.data(), png.size(), "plot");
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, 500);
  const std::string svg = plot_measured_svg(f, options);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find(">RMSE vs snr: camera.png &amp; &lt;b&gt;</text>"), std::string::npos);
  EXPECT_NE(svg.find(">no data: accumulation (not-invertible)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">100</text>"), std::string::npos);  // 100 on the snr axis
  MeasuredFigure wide = f;
  wide.x = {1e3, 1e4, 1e5, 1e6, 1e7};
  EXPECT_NE(plot_measured_svg(wide, options).find(">10<tspan"), std::string::npos);  // 10^5
  EXPECT_EQ(svg, plot_measured_svg(f, options));
  EXPECT_EQ(png, plot_measured_png(f, options));
}

// The smallest picture still draws, the plot area inside the picture.
TEST(MeasuredPlot, SmallestPictureDraws) {
  MeasuredFigure f = falling_figure();
  f.notes = {"no data: accumulation (not-invertible)"};
  f.open_key = "RMSE margin < 3B";
  f.series[0].open = {true, true, false, false, false};
  const PlotOptions options{kPlotMinSide, kPlotMinSide, std::string(200, 'T')};
  const MeasuredLayout l = layout_measured(f, options.title, kPlotMinSide, kPlotMinSide);
  EXPECT_GE(l.plot.left, 0.0);
  EXPECT_LE(l.plot.right, kPlotMinSide);
  EXPECT_GT(l.plot.height(), 0.0) << l.plot.top << " " << l.plot.bottom;
  EXPECT_GT(l.plot.width(), 0.0) << l.plot.left << " " << l.plot.right;
  const std::vector<std::uint8_t> png = plot_measured_png(f, options);
  EXPECT_EQ(decode_png(png.data(), png.size(), "plot").width, kPlotMinSide);
  EXPECT_NE(plot_measured_svg(f, options).find("</svg>"), std::string::npos);
}

TEST(MeasuredPlot, RefusesWhatItCannotDraw) {
  MeasuredFigure f = falling_figure();
  MeasuredFigure empty = f;
  for (MeasuredSeries& s : empty.series) s.measured.assign(5, kNan);
  EXPECT_TRUE(test::throws_error([&] { plot_measured_png(empty); }, ErrorKind::kUsage,
                                 {"at least one measured point"}));
  MeasuredFigure short_series = f;
  short_series.series[0].predicted.pop_back();
  EXPECT_TRUE(test::throws_error([&] { plot_measured_svg(short_series); }, ErrorKind::kUsage,
                                 {"series 'snapshot' has 4 values for 5 x values"}));
  MeasuredFigure negative = f;
  negative.x[0] = -1.0;
  EXPECT_TRUE(test::throws_error([&] { plot_measured_png(negative); }, ErrorKind::kUsage,
                                 {"> 0 on a logarithmic axis"}));
  MeasuredFigure none = f;
  none.series.clear();
  EXPECT_TRUE(test::throws_error([&] { plot_measured_png(none); }, ErrorKind::kUsage,
                                 {"1 to 8 series, got 0"}));
}

}  // namespace
}  // namespace fss
