// The layout of a figure of measurements (plot_layout.h, layout_measured):
// the axes' ranges and ticks, the title, labels and notes fitted to the
// picture, and the legend in a corner that no data reaches.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/plot_draw.h"
#include "io/plot_layout.h"

namespace fss::plotting {

namespace {

bool finite_value(const std::vector<double>& values, std::size_t j) {
  return j < values.size() && std::isfinite(values[j]);
}

// The half-height of the bar at j (0 when there is none).
double bar(const MeasuredSeries& s, std::size_t j) {
  return finite_value(s.error, j) && s.error[j] > 0.0 ? s.error[j] : 0.0;
}

// The smallest and largest values to show: the points, their bars' ends (those > 0 only on a
// log axis) and the predictions.
std::pair<double, double> value_range(const MeasuredFigure& f, bool log) {
  double low = HUGE_VAL, high = -HUGE_VAL;
  const auto take = [&](double v) {
    if (std::isfinite(v) && (!log || v > 0.0)) low = std::min(low, v), high = std::max(high, v);
  };
  for (const MeasuredSeries& s : f.series) {
    for (std::size_t j = 0; j < f.x.size(); ++j) {
      if (finite_value(s.measured, j)) {
        take(s.measured[j]);
        take(s.measured[j] - bar(s, j));
        take(s.measured[j] + bar(s, j));
      }
      if (finite_value(s.predicted, j)) take(s.predicted[j]);
    }
  }
  return {low, high};
}

// kAuto: logarithmic when every point and prediction is > 0 and they span a decade or more.
bool log_y(const MeasuredFigure& f) {
  if (f.y_scale != AxisScale::kAuto) return f.y_scale == AxisScale::kLog;
  double low = HUGE_VAL, high = -HUGE_VAL;
  for (const MeasuredSeries& s : f.series) {
    for (std::size_t j = 0; j < f.x.size(); ++j) {
      for (const std::vector<double>* values : {&s.measured, &s.predicted}) {
        if (finite_value(*values, j))
          low = std::min(low, (*values)[j]), high = std::max(high, (*values)[j]);
      }
    }
  }
  return low > 0.0 && high >= 10.0 * low;
}

// The y axis's range and ticks: linear from 0 (or below, for negative values) to 6 % above the
// largest value; logarithmic 5 % of the span (at least 0.05 decade) beyond both ends.
AxisLayout y_axis(const MeasuredFigure& f) {
  AxisLayout axis;
  axis.log = log_y(f);
  auto [low, high] = value_range(f, axis.log);
  if (!(low <= high)) low = axis.log ? 1.0 : 0.0, high = axis.log ? 10.0 : 1.0;
  if (axis.log) {
    const double pad = std::max(0.05, 0.05 * std::log10(high / low));
    axis.low = low / std::pow(10.0, pad);
    axis.high = high * std::pow(10.0, pad);
    axis.ticks = log_ticks(axis.low, axis.high);
    return axis;
  }
  if (!(high > low)) high = low + std::max(1.0, std::abs(low)) * 0.1;
  const double span = high - low;
  axis.low = low >= 0.0 ? 0.0 : low - 0.05 * span;
  axis.high = high + 0.06 * (high - axis.low);
  axis.ticks = linear_ticks(axis.low, axis.high);
  return axis;
}

// The x axis: 4 % of the span beyond the first and last x (by log10 on a log axis).
AxisLayout x_axis(const MeasuredFigure& f) {
  AxisLayout axis;
  axis.log = f.log_x;
  const double first = f.log_x ? std::log10(f.x.front()) : f.x.front();
  const double last = f.log_x ? std::log10(f.x.back()) : f.x.back();
  const double pad = last > first ? 0.04 * (last - first)
                     : f.log_x    ? 0.3
                                  : 0.5 * std::max(1.0, std::abs(first));
  axis.low = f.log_x ? std::pow(10.0, first - pad) : first - pad;
  axis.high = f.log_x ? std::pow(10.0, last + pad) : last + pad;
  axis.ticks = f.log_x ? log_ticks(axis.low, axis.high) : linear_ticks(axis.low, axis.high);
  return axis;
}

// The legend's rows: the series with a point or a prediction.
std::vector<LegendRow> legend_rows(const MeasuredFigure& f, const std::vector<int>& colours) {
  std::vector<LegendRow> rows;
  for (std::size_t i = 0; i < f.series.size(); ++i) {
    const MeasuredSeries& s = f.series[i];
    bool point = false, line = false;
    for (std::size_t j = 0; j < f.x.size(); ++j) {
      point = point || finite_value(s.measured, j);
      line = line || finite_value(s.predicted, j);
    }
    if (point || line)
      rows.push_back({LegendMark::kSeries, ellipsize(s.name, 48), colours[i], line});
  }
  return rows;
}

// The key of the marks: the points (with a bar when one has one), the predicted line when a
// series has one, the open marker when a point is open.
std::vector<LegendRow> key_rows(const MeasuredFigure& f) {
  bool line = false, open = false, any_bar = false;
  for (const MeasuredSeries& s : f.series) {
    for (std::size_t j = 0; j < f.x.size(); ++j) {
      line = line || finite_value(s.predicted, j);
      if (!finite_value(s.measured, j)) continue;
      open = open || (j < s.open.size() && s.open[j]);
      any_bar = any_bar || bar(s, j) > 0.0;
    }
  }
  std::vector<LegendRow> rows = {
      {LegendMark::kPoints, ellipsize(f.points_key, 60), 0, false, any_bar}};
  if (line) rows.push_back({LegendMark::kPredicted, ellipsize(f.predicted_key, 60), 0, true});
  if (open && !f.open_key.empty()) rows.push_back({LegendMark::kOpen, ellipsize(f.open_key, 60)});
  return rows;
}

// The key's entries side by side from `left`, onto a new row when one would pass `right`; y
// from 0 at the key's top.
std::vector<KeyItem> key_items(const std::vector<LegendRow>& rows, double left, double right) {
  std::vector<KeyItem> items;
  double x = left, y = LegendLayout::kRowHeight / 2.0;
  for (const LegendRow& row : rows) {
    const double width =
        LegendLayout::kSample + 6.0 + text_width(row.text, LegendLayout::kTextSize);
    if (x > left && x + width > right) x = left, y += LegendLayout::kRowHeight;
    items.push_back({row, x, y});
    x += width + 22.0;
  }
  return items;
}

// The width of the legend's widest entry: its mark and its text.
double entry_width(const std::vector<LegendRow>& rows) {
  double text = 0.0;
  for (const LegendRow& row : rows) {
    text = std::max(text, text_width(row.text, LegendLayout::kTextSize));
  }
  return LegendLayout::kSample + 6.0 + text;
}

// The legend box's size for its entries in its columns.
Rect legend_size(const LegendLayout& legend) {
  const double columns = legend.columns;
  const double width = 2 * LegendLayout::kPadding + columns * legend.column_width +
                       (columns - 1) * LegendLayout::kColumnGap;
  const double height = 2 * LegendLayout::kPadding +
                        LegendLayout::kRowHeight * static_cast<double>(legend.rows_per_column());
  return {0.0, 0.0, width, height};
}

bool overlaps(const Rect& a, const Rect& b) {
  return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
}

// The legend in the first corner of the plot area (top right, top left,
// bottom right, bottom left) that holds none of the data, inset by 6
// pixels; else none.
bool place_inside(const MeasuredFigure& f, MeasuredLayout& layout, const Rect& size) {
  const Rect& p = layout.plot;
  constexpr double kInset = 6.0, kClearance = 3.0;
  if (size.width() > p.width() - 2 * kInset || size.height() > p.height() - 2 * kInset)
    return false;
  const std::vector<Rect> marks = data_marks(f, layout);
  const double lefts[] = {p.right - kInset - size.width(), p.left + kInset};
  const double tops[] = {p.top + kInset, p.bottom - kInset - size.height()};
  for (const double top : tops) {
    for (const double left : lefts) {
      const Rect box{left, top, left + size.width(), top + size.height()};
      const Rect clear{box.left - kClearance, box.top - kClearance, box.right + kClearance,
                       box.bottom + kClearance};
      if (std::none_of(marks.begin(), marks.end(),
                       [&](const Rect& m) { return overlaps(m, clear); })) {
        layout.legend.box = box;
        return true;
      }
    }
  }
  return false;
}

// The plot area's edges: under the title, right of the y label and tick
// labels, `right` from the picture's right edge, above the tick labels, the x
// label, `below` pixels (for a legend), the key and the notes. `key` is the
// key's entries with y from 0 at its top.
void frame_plot(MeasuredLayout& layout, const std::vector<KeyItem>& key, double right,
                double below = 0.0) {
  double label_width = 0.0;
  for (const Tick& t : layout.y.ticks)
    label_width = std::max(label_width, tick_label_width(t, kTickLabelSize));
  layout.y_label_x = 6.0 + 0.5 * 1.3 * kAxisLabelSize;
  layout.plot.left = std::ceil(6.0 + 1.3 * kAxisLabelSize + 8.0 + label_width + 9.0);
  layout.plot.top = std::ceil(layout.title_top + layout.title.height() + 8.0);
  layout.plot.right = std::floor(layout.width - right);
  double key_height = 0.0;
  for (const KeyItem& item : key)
    key_height = std::max(key_height, item.y + LegendLayout::kRowHeight / 2.0);
  const double key_top =
      (layout.notes.lines.empty() ? layout.height - 4.0 : layout.notes_top - 2.0) - key_height;
  layout.key = key;
  for (KeyItem& item : layout.key) item.y += key_top;
  layout.x_label_y = key_top - below - 2.0 - 0.5 * 1.3 * kAxisLabelSize;
  layout.plot.bottom = std::floor(layout.x_label_y - 0.5 * 1.3 * kAxisLabelSize - 30.0);
  layout.x.pixel_low = layout.plot.left;
  layout.x.pixel_high = layout.plot.right;
  layout.y.pixel_low = layout.plot.bottom;
  layout.y.pixel_high = layout.plot.top;
}

// The legend outside the plot area: right of it when narrow (at most 30 % of
// the picture's width), else under the x label in as many columns as fit.
void place_outside(MeasuredLayout& layout, const std::vector<KeyItem>& key) {
  LegendLayout& legend = layout.legend;
  legend.inside = false;
  Rect size = legend_size(legend);
  if (size.width() <= 0.3 * layout.width) {
    frame_plot(layout, key, 18.0 + size.width() + 4.0);
    const double left = layout.plot.right + 12.0;
    legend.box = {left, layout.plot.top, left + size.width(), layout.plot.top + size.height()};
    return;
  }
  const double room = layout.width - 16.0 - 2 * LegendLayout::kPadding + LegendLayout::kColumnGap;
  legend.columns = static_cast<int>(
      std::clamp(std::floor(room / (legend.column_width + LegendLayout::kColumnGap)), 1.0,
                 static_cast<double>(legend.rows.size())));
  size = legend_size(legend);
  frame_plot(layout, key, 18.0, size.height() + 4.0);
  const double top = layout.x_label_y + 0.5 * 1.3 * kAxisLabelSize + 3.0;
  const double left = std::max(8.0, (layout.width - size.width()) / 2.0);
  legend.box = {left, top, left + size.width(), top + size.height()};
}

// True when the plot area keeps at least 40 % of the picture's width and 30 % of its height.
bool roomy(const MeasuredLayout& layout) {
  return layout.plot.width() >= 0.4 * layout.width && layout.plot.height() >= 0.3 * layout.height;
}

// The title and the notes fitted to the picture: the notes left out, then the title on one line,
// when the plot area would be cramped (a small picture).
void fit_texts(const MeasuredFigure& f, const std::string& title, MeasuredLayout& layout,
               const std::vector<KeyItem>& key) {
  layout.title = fit_text(title, layout.width - 16.0, kFigureTitleSize, 10.0);
  layout.title_top = 8.0;
  layout.notes.size = kNoteSize;
  for (const std::string& note : f.notes) {
    for (std::string& line : fit_text(note, layout.width - 16.0, kNoteSize, kNoteSize, 1).lines) {
      layout.notes.lines.push_back(std::move(line));
    }
  }
  layout.notes_top = layout.height - 6.0 - layout.notes.height();
  frame_plot(layout, key, 18.0);
  if (!roomy(layout)) {
    layout.notes.lines.clear();
    layout.notes_top = layout.height - 6.0;
    layout.title = fit_text(title, layout.width - 16.0, 10.0, 10.0, 1);
  }
}

}  // namespace

MeasuredLayout layout_measured(const MeasuredFigure& f, const std::string& title, int width,
                               int height) {
  MeasuredLayout layout;
  layout.width = width;
  layout.height = height;
  for (std::size_t i = 0; i < f.series.size(); ++i) {
    const int colour = f.series[i].colour >= 0 ? f.series[i].colour : static_cast<int>(i);
    layout.colours.push_back(colour % kMaxSeries);
  }
  layout.x = x_axis(f);
  layout.y = y_axis(f);
  layout.legend.rows = legend_rows(f, layout.colours);
  layout.legend.column_width = entry_width(layout.legend.rows);
  std::vector<KeyItem> key = key_items(key_rows(f), 8.0, width - 8.0);
  fit_texts(f, title, layout, key);
  if (!roomy(layout)) {  // a small picture: no key
    key.clear();
    frame_plot(layout, key, 18.0);
  }
  if (!place_inside(f, layout, legend_size(layout.legend))) {
    place_outside(layout, key);
    if (!roomy(layout)) {  // no room beside the plot area either: over its top right corner
      layout.legend.columns = 1;
      frame_plot(layout, key, 18.0);
      const Rect size = legend_size(layout.legend);
      layout.legend.box = {layout.plot.right - 6.0 - size.width(), layout.plot.top + 6.0,
                           layout.plot.right - 6.0, layout.plot.top + 6.0 + size.height()};
    }
  }
  double widest = 0.0;
  for (const std::string& line : layout.title.lines) {
    widest = std::max(widest, text_width(line, layout.title.size));
  }
  layout.title_x = std::clamp((layout.plot.left + layout.plot.right) / 2.0, 8.0 + widest / 2.0,
                              std::max(8.0 + widest / 2.0, width - 8.0 - widest / 2.0));
  layout.x_label = fit_text(f.x_label, layout.plot.width(), kAxisLabelSize, 9.0, 1);
  layout.y_label = fit_text(f.y_label, layout.plot.height(), kAxisLabelSize, 9.0, 1);
  return layout;
}

std::vector<PointMark> point_marks(const MeasuredFigure& f, const MeasuredLayout& layout,
                                   std::size_t i) {
  const MeasuredSeries& s = f.series[i];
  const AxisLayout& y = layout.y;
  std::vector<PointMark> marks;
  for (std::size_t j = 0; j < f.x.size(); ++j) {
    if (!finite_value(s.measured, j) || (y.log && !(s.measured[j] > 0.0))) continue;
    PointMark m;
    m.x = layout.x.pixel(f.x[j]);
    m.y = y.pixel(s.measured[j]);
    m.open = j < s.open.size() && s.open[j];
    m.bar_top = m.bar_bottom = m.y;
    if (const double e = bar(s, j); e > 0.0) {
      const double top = s.measured[j] + e, bottom = s.measured[j] - e;
      m.top_cap = top <= y.high;
      m.bottom_cap = bottom >= y.low;
      m.bar_top = y.pixel(std::min(top, y.high));
      m.bar_bottom = y.pixel(m.bottom_cap ? bottom : y.low);
    }
    marks.push_back(m);
  }
  return marks;
}

std::vector<std::vector<std::size_t>> predicted_runs(const MeasuredFigure& f,
                                                     const MeasuredLayout& layout, std::size_t i) {
  const MeasuredSeries& s = f.series[i];
  std::vector<std::vector<std::size_t>> runs(1);
  for (std::size_t j = 0; j < f.x.size(); ++j) {
    if (finite_value(s.predicted, j) && (!layout.y.log || s.predicted[j] > 0.0)) {
      runs.back().push_back(j);
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  std::erase_if(runs, [](const std::vector<std::size_t>& run) { return run.empty(); });
  return runs;
}

std::vector<Rect> data_marks(const MeasuredFigure& f, const MeasuredLayout& layout) {
  std::vector<Rect> marks;
  const double r = kMarkerRadius + 1.0;
  for (std::size_t i = 0; i < f.series.size(); ++i) {
    for (const PointMark& m : point_marks(f, layout, i)) {
      marks.push_back({m.x - r, m.y - r, m.x + r, m.y + r});
      marks.push_back({m.x - kBarCap, m.bar_top, m.x + kBarCap, m.bar_bottom});
    }
    for (const std::vector<std::size_t>& run : predicted_runs(f, layout, i)) {
      if (run.size() == 1) {
        const double x = layout.x.pixel(f.x[run[0]]);
        const double y = layout.y.pixel(f.series[i].predicted[run[0]]);
        marks.push_back({x - kPredictedDash, y - 1.5, x + kPredictedDash, y + 1.5});
      }
      for (std::size_t k = 0; k + 1 < run.size(); ++k) {
        const double x0 = layout.x.pixel(f.x[run[k]]),
                     y0 = layout.y.pixel(f.series[i].predicted[run[k]]);
        const double x1 = layout.x.pixel(f.x[run[k + 1]]);
        const double y1 = layout.y.pixel(f.series[i].predicted[run[k + 1]]);
        const int steps = static_cast<int>(std::ceil(std::hypot(x1 - x0, y1 - y0))) + 1;
        for (int step = 0; step <= steps; ++step) {
          const double t = static_cast<double>(step) / steps;
          const double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
          marks.push_back({x - 1.5, y - 1.5, x + 1.5, y + 1.5});
        }
      }
    }
  }
  return marks;
}

}  // namespace fss::plotting
