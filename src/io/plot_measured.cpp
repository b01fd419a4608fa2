// The figure of measurements against their prediction as PNG (fss/io/plot.h,
// plot_measured_png), drawn with PLplot in the pixels of its layout
// (plot_layout.h), and the checks of its data shared with the SVG.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "io/plot_backend.h"
#include "io/plot_draw.h"
#include "io/plot_layout.h"

namespace fss {

namespace plotting {

void check_measured(const MeasuredFigure& f, const PlotOptions& options) {
  check_size(options);
  if (f.x.empty()) throw_usage_error("a figure of measurements needs at least one x value");
  if (f.series.empty() || static_cast<int>(f.series.size()) > kMaxSeries) {
    throw_usage_error("a figure of measurements takes 1 to " + std::to_string(kMaxSeries) +
                      " series, got " + std::to_string(f.series.size()));
  }
  for (std::size_t i = 0; i < f.x.size(); ++i) {
    if (!std::isfinite(f.x[i]) || (i > 0 && !(f.x[i] > f.x[i - 1])) ||
        (f.log_x && !(f.x[i] > 0.0))) {
      throw_usage_error(std::string("the x values of a figure must be finite and increasing") +
                        (f.log_x ? ", and > 0 on a logarithmic axis" : ""));
    }
  }
  bool any = false;
  for (const MeasuredSeries& s : f.series) {
    for (const std::vector<double>* values : {&s.measured, &s.error, &s.predicted}) {
      if (values != &s.measured && values->empty()) continue;
      if (values->size() != f.x.size()) {
        throw_usage_error("series '" + s.name + "' has " + std::to_string(values->size()) +
                          " values for " + std::to_string(f.x.size()) + " x values");
      }
    }
    if (!s.open.empty() && s.open.size() != f.x.size()) {
      throw_usage_error("series '" + s.name + "' has " + std::to_string(s.open.size()) +
                        " open marks for " + std::to_string(f.x.size()) + " x values");
    }
    any = any || std::any_of(s.measured.begin(), s.measured.end(),
                             [](double v) { return std::isfinite(v); });
  }
  if (!any) throw_usage_error("a figure of measurements needs at least one measured point");
}

std::string measured_title(const MeasuredFigure& f, const PlotOptions& options) {
  return options.title.empty() ? f.y_label + " against " + f.x_label : options.title;
}

}  // namespace plotting

namespace {

using namespace plotting;  // NOLINT: the private drawing helpers of the plots

// PLplot's character height (Canvas::text_height) that sets text at one pixel per em: the
// cairo driver draws a height of h pixels at 4/3 h pixels per em.
constexpr double kPlplotSizePerEm = 0.75;

// Drawing in the layout's pixels (y down) over PLplot's pixel window (y up).
class Pen {
 public:
  explicit Pen(const Canvas& canvas) : canvas_(canvas) { canvas.pixel_window(); }

  void line(double x0, double y0, double x1, double y1, PLINT colour, double width) const {
    plcol0(colour);
    plwidth(width);
    pllsty(1);
    pljoin(x0, flip(y0), x1, flip(y1));
  }
  void polyline(const std::vector<double>& x, std::vector<double> y, PLINT colour,
                double width) const {
    if (x.size() < 2) return;
    for (double& v : y) v = flip(v);
    plcol0(colour);
    plwidth(width);
    pllsty(1);
    plline(static_cast<PLINT>(x.size()), x.data(), y.data());
  }
  // A circle filled with `fill`, its edge in `edge`.
  void circle(double cx, double cy, double radius, PLINT fill, PLINT edge, double width) const {
    constexpr int kSides = 32;
    PLFLT px[kSides + 1], py[kSides + 1];
    for (int i = 0; i <= kSides; ++i) {
      px[i] = cx + radius * std::cos(2.0 * M_PI * i / kSides);
      py[i] = flip(cy) + radius * std::sin(2.0 * M_PI * i / kSides);
    }
    plcol0(fill);
    plfill(kSides, px, py);
    plcol0(edge);
    plwidth(width);
    pllsty(1);
    plline(kSides + 1, px, py);
  }
  // PLplot text (see literal()) centred vertically at y; `just` 0 left, 0.5 centre, 1 right;
  // turned a quarter left when `up`.
  void text(double x, double y, double just, double size, PLINT colour, const std::string& content,
            bool up = false) const {
    canvas_.text_height(size * kPlplotSizePerEm);
    plcol0(colour);
    // PLplot puts the middle of the capitals on the reference point.
    if (up) {
      plptex(x, flip(y), 0.0, 1.0, just, content.c_str());
    } else {
      plptex(x, flip(y), 1.0, 0.0, just, content.c_str());
    }
  }
  void rect(const Rect& r, PLINT fill, PLINT edge) const {
    PLFLT px[5] = {r.left, r.right, r.right, r.left, r.left};
    PLFLT py[5] = {flip(r.top), flip(r.top), flip(r.bottom), flip(r.bottom), flip(r.top)};
    if (fill >= 0) {
      plcol0(fill);
      plfill(4, px, py);
    }
    plcol0(edge);
    plwidth(1.0);
    pllsty(1);
    plline(5, px, py);
  }

 private:
  double flip(double y) const { return canvas_.height() - y; }
  const Canvas& canvas_;
};

std::string tick_text(const Tick& t) {
  return t.exponent.empty() ? literal(t.label)
                            : literal(t.label) + "#u" + literal(t.exponent) + "#d";
}

void draw_ticks(const Pen& pen, const MeasuredLayout& l) {
  const Rect& p = l.plot;
  for (const Tick& t : l.x.ticks) {
    const double x = l.x.pixel(t.value), length = t.label.empty() ? 3.0 : 6.0;
    pen.line(x, p.bottom, x, p.bottom - length, kInk, 1.0);
    pen.line(x, p.top, x, p.top + length, kInk, 1.0);
    if (!t.label.empty()) pen.text(x, p.bottom + 15.0, 0.5, kTickLabelSize, kInk, tick_text(t));
  }
  for (const Tick& t : l.y.ticks) {
    const double y = l.y.pixel(t.value), length = t.label.empty() ? 3.0 : 6.0;
    pen.line(p.left, y, p.left + length, y, kInk, 1.0);
    pen.line(p.right, y, p.right - length, y, kInk, 1.0);
    if (!t.label.empty()) pen.text(p.left - 7.0, y, 1.0, kTickLabelSize, kInk, tick_text(t));
  }
}

void draw_text_blocks(const Pen& pen, const MeasuredLayout& l) {
  for (std::size_t i = 0; i < l.title.lines.size(); ++i) {
    pen.text(l.title_x, l.title_top + (i + 0.5) * l.title.line_height(), 0.5, l.title.size, kInk,
             literal(l.title.lines[i]));
  }
  const double centre_x = (l.plot.left + l.plot.right) / 2.0;
  pen.text(centre_x, l.x_label_y, 0.5, l.x_label.size, kInk, literal(l.x_label.lines.front()));
  pen.text(l.y_label_x, (l.plot.top + l.plot.bottom) / 2.0, 0.5, l.y_label.size, kInk,
           literal(l.y_label.lines.front()), true);
  for (std::size_t i = 0; i < l.notes.lines.size(); ++i) {
    pen.text(8.0, l.notes_top + (i + 0.5) * l.notes.line_height(), 0.0, l.notes.size, kReference,
             literal(l.notes.lines[i]));
  }
}

void draw_series(const Pen& pen, const MeasuredFigure& f, const MeasuredLayout& l, std::size_t i) {
  const MeasuredSeries& s = f.series[i];
  const PLINT colour = static_cast<PLINT>(kSeries + l.colours[i]);
  for (const std::vector<std::size_t>& run : predicted_runs(f, l, i)) {
    std::vector<double> x, y;
    for (const std::size_t j : run) {
      x.push_back(l.x.pixel(f.x[j]));
      y.push_back(l.y.pixel(s.predicted[j]));
    }
    if (run.size() == 1) {  // a lone value: a dash
      x = {x[0] - kPredictedDash, x[0] + kPredictedDash};
      y.push_back(y[0]);
    }
    pen.polyline(x, y, colour, 1.8);
  }
  for (const PointMark& m : point_marks(f, l, i)) {
    if (m.bar_top < m.bar_bottom) {
      pen.line(m.x, m.bar_top, m.x, m.bar_bottom, colour, 1.3);
      if (m.top_cap) pen.line(m.x - kBarCap, m.bar_top, m.x + kBarCap, m.bar_top, colour, 1.3);
      if (m.bottom_cap)
        pen.line(m.x - kBarCap, m.bar_bottom, m.x + kBarCap, m.bar_bottom, colour, 1.3);
    }
    pen.circle(m.x, m.y, kMarkerRadius, m.open ? kBackground : colour, colour, m.open ? 1.6 : 1.0);
  }
}

// A legend row's or key entry's mark from x0 over LegendLayout::kSample, centred at y.
void draw_mark(const Pen& pen, const LegendRow& row, double x0, double y) {
  const double xm = x0 + LegendLayout::kSample / 2.0, x1 = x0 + LegendLayout::kSample;
  const PLINT colour =
      row.mark == LegendMark::kSeries ? static_cast<PLINT>(kSeries + row.colour) : kInk;
  if (row.has_line) pen.line(x0, y, x1, y, colour, 1.8);
  if (row.mark == LegendMark::kPoints && row.has_bar) {
    pen.line(xm, y - 6.0, xm, y + 6.0, colour, 1.3);
    pen.line(xm - kBarCap, y - 6.0, xm + kBarCap, y - 6.0, colour, 1.3);
    pen.line(xm - kBarCap, y + 6.0, xm + kBarCap, y + 6.0, colour, 1.3);
  }
  if (row.mark != LegendMark::kPredicted) {
    const bool open = row.mark == LegendMark::kOpen;
    pen.circle(xm, y, kMarkerRadius, open ? kBackground : colour, colour, open ? 1.6 : 1.0);
  }
}

void draw_legend_and_key(const Pen& pen, const MeasuredLayout& l) {
  const LegendLayout& g = l.legend;
  pen.rect(g.box, kBackground, kGrid);
  for (std::size_t i = 0; i < g.rows.size(); ++i) {
    draw_mark(pen, g.rows[i], g.entry_x(i), g.entry_y(i));
    pen.text(g.entry_x(i) + LegendLayout::kSample + 6.0, g.entry_y(i), 0.0, LegendLayout::kTextSize,
             kInk, literal(g.rows[i].text));
  }
  for (const KeyItem& item : l.key) {
    draw_mark(pen, item.row, item.x, item.y);
    pen.text(item.text_x(), item.y, 0.0, LegendLayout::kTextSize, kInk, literal(item.row.text));
  }
}

}  // namespace

std::vector<std::uint8_t> plot_measured_png(const MeasuredFigure& figure,
                                            const PlotOptions& options) {
  check_measured(figure, options);
  const MeasuredLayout l =
      layout_measured(figure, measured_title(figure, options), options.width, options.height);
  return render_plot(options, [&](const Canvas& canvas) {
    const Pen pen(canvas);
    for (std::size_t i = 0; i < figure.series.size(); ++i) draw_series(pen, figure, l, i);
    pen.rect(l.plot, -1, kInk);
    draw_ticks(pen, l);
    draw_text_blocks(pen, l);
    draw_legend_and_key(pen, l);
  });
}

}  // namespace fss
