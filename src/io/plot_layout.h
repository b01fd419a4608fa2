// Private to the plots (src/io/plot_*.cpp): the layout of a figure of
// measurements (fss/io/plot.h, MeasuredFigure), shared by its PNG and SVG
// renderers, and the estimated width of text. Positions are in pixels of the
// picture, x to the right and y down from its top-left corner.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "fss/io/plot.h"

namespace fss::plotting {

// The width of `text` (UTF-8) set in DejaVu Sans at `size` pixels per em, by
// the font's advance widths and a little more: text that fits by this fits
// on the picture. Characters outside ASCII count one em.
double text_width(std::string_view text, double size);

// Lines of text set at one size.
struct TextBlock {
  std::vector<std::string> lines;
  double size = 0.0;  // pixels per em
  double line_height() const { return 1.3 * size; }
  double height() const { return line_height() * static_cast<double>(lines.size()); }
};

// `text` in at most `max_lines` lines each at most `width` wide, at the
// largest whole size from `size` down to `min_size` that fits; cut short in
// its middle at `min_size` when nothing fits.
TextBlock fit_text(const std::string& text, double width, double size, double min_size,
                   int max_lines = 2);

// A tick of an axis; `label` empty for a minor tick. A label with an
// exponent reads label, then the exponent raised: "10" and "2" for 10^2.
struct Tick {
  double value = 0.0;
  std::string label;
  std::string exponent;
};

// The width of a tick's label at `size`.
double tick_label_width(const Tick& tick, double size);

// Ticks of a logarithmic axis over [low, high] (0 < low < high): every power
// of ten labelled 10^k; 2 and 5 times them labelled m×10^k when fewer than 3
// labels show; unlabelled ticks at the other integer multiples when the axis
// spans less than 6 decades. An axis too short for 3 such labels gets
// linear_ticks(low, high, 4).
std::vector<Tick> log_ticks(double low, double high);

// Ticks of a linear axis over [low, high]: steps of 1, 2 or 5 times a power
// of ten, about `target` of them and at least 3, all labelled.
std::vector<Tick> linear_ticks(double low, double high, int target = 6);

struct Rect {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
  double width() const { return right - left; }
  double height() const { return bottom - top; }
};

// One axis: its range in data units and where its ends fall on the picture.
struct AxisLayout {
  bool log = false;
  double low = 0.0, high = 1.0;
  double pixel_low = 0.0, pixel_high = 1.0;
  std::vector<Tick> ticks;
  // The pixel of `value`; log axes by log10 (the caller passes values > 0).
  double pixel(double value) const;
  bool contains(double value) const { return value >= low && value <= high; }
};

enum class LegendMark {
  kSeries,     // the series' colour: a line with a marker, or a marker
  kPoints,     // ink: a marker with its bar
  kPredicted,  // ink: a line
  kOpen,       // ink: an open marker
};

struct LegendRow {
  LegendMark mark = LegendMark::kSeries;
  std::string text;
  int colour = 0;         // of the series' palette (kSeries only)
  bool has_line = false;  // kSeries: the series has a predicted curve
  bool has_bar = false;   // kPoints: a point has an error bar
};

// The series' legend: a box of entries in columns, filled column by column.
struct LegendLayout {
  Rect box;
  std::vector<LegendRow> rows;  // kSeries
  bool inside = true;           // in a corner of the plot area, else right of it or below it
  int columns = 1;
  double column_width = 0.0;  // an entry's mark and text, without the gap between columns
  static constexpr double kRowHeight = 19.0;
  static constexpr double kPadding = 6.0;
  static constexpr double kSample = 28.0;  // width of a row's mark
  static constexpr double kTextSize = 13.0;
  static constexpr double kColumnGap = 22.0;
  std::size_t rows_per_column() const {
    return (rows.size() + static_cast<std::size_t>(columns) - 1) /
           static_cast<std::size_t>(columns);
  }
  // Where entry i's mark starts, and the vertical centre of its line.
  double entry_x(std::size_t i) const {
    return box.left + kPadding +
           static_cast<double>(i / rows_per_column()) * (column_width + kColumnGap);
  }
  double entry_y(std::size_t i) const {
    return box.top + kPadding + (static_cast<double>(i % rows_per_column()) + 0.5) * kRowHeight;
  }
};

// An entry of the key of the marks (points, predicted, open), in ink: its
// mark from x to x + LegendLayout::kSample, then its text, centred at y.
struct KeyItem {
  LegendRow row;
  double x = 0.0, y = 0.0;
  double text_x() const { return x + LegendLayout::kSample + 6.0; }
};

// Sizes of the figures of measurements, in pixels.
inline constexpr double kMarkerRadius = 4.0;
inline constexpr double kBarCap = 3.5;         // half-width of an error bar's ends
inline constexpr double kPredictedDash = 9.0;  // half-width of a lone predicted value's dash
inline constexpr double kTickLabelSize = 13.0;
inline constexpr double kAxisLabelSize = 14.0;
inline constexpr double kFigureTitleSize = 15.0;
inline constexpr double kNoteSize = 12.0;

struct MeasuredLayout {
  int width = 0, height = 0;
  TextBlock title;  // its first line at title_top, centred at title_x
  double title_top = 0.0;
  double title_x = 0.0;  // over the plot area, or nearer the picture's centre if need be
  Rect plot;
  AxisLayout x, y;
  TextBlock x_label, y_label;  // centred under the plot area and left of it (turned)
  double x_label_y = 0.0;      // centre of the x label's line
  double y_label_x = 0.0;      // centre of the y label's (turned) line
  LegendLayout legend;
  std::vector<KeyItem> key;  // in rows under the x label, from the plot area's left
  TextBlock notes;           // left-aligned under the key
  double notes_top = 0.0;
  std::vector<int> colours;  // per series, of the series' palette
};

// The layout of `figure` under `title` on a picture of width x height
// (checked by the caller: plot_measured_png/svg).
MeasuredLayout layout_measured(const MeasuredFigure& figure, const std::string& title, int width,
                               int height);

// A measured point of a series as drawn: its marker's centre and its bar's
// ends (bar_top == bar_bottom: no bar), each end capped unless cut at the
// plot area's edge.
struct PointMark {
  double x = 0.0, y = 0.0;
  double bar_top = 0.0, bar_bottom = 0.0;
  bool top_cap = false, bottom_cap = false;
  bool open = false;
};

// The points of series `i` that the layout shows (finite, and > 0 on a log axis).
std::vector<PointMark> point_marks(const MeasuredFigure& figure, const MeasuredLayout& layout,
                                   std::size_t i);

// The runs of consecutive x indices over which series `i`'s prediction is
// drawn (finite, and > 0 on a log axis): a line, or a run of one value a
// dash kPredictedDash pixels on each side of its x.
std::vector<std::vector<std::size_t>> predicted_runs(const MeasuredFigure& figure,
                                                     const MeasuredLayout& layout, std::size_t i);

// The pixels that the data of `figure` cover in `layout`, as small
// rectangles: each marker, each error bar, and the predicted curves sampled
// every pixel along their segments.
std::vector<Rect> data_marks(const MeasuredFigure& figure, const MeasuredLayout& layout);

// A usage fss::Error for a figure plot_measured_png/svg cannot draw (plot.h).
void check_measured(const MeasuredFigure& figure, const PlotOptions& options);

// The figure's title: options.title, or "Y against X".
std::string measured_title(const MeasuredFigure& figure, const PlotOptions& options);

}  // namespace fss::plotting
