// The figure of measurements against their prediction as SVG (fss/io/plot.h,
// plot_measured_svg): the PNG's layout (plot_layout.h) written as SVG
// elements, the text in DejaVu Sans (or the viewer's sans-serif).
#include <array>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "core/text_util.h"
#include "fss/io/plot.h"
#include "io/plot_backend.h"
#include "io/plot_layout.h"

namespace fss {

namespace {

using namespace plotting;  // NOLINT: the private drawing helpers of the plots

std::string escaped(std::string_view text) {
  std::string out;
  for (const char c : detail::sanitize_utf8(text)) {
    if (c == '&') {
      out += "&amp;";
    } else if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '"') {
      out += "&quot;";
    } else {
      out += c;
    }
  }
  return out;
}

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  return buffer;
}

// The colour #rrggbb of a palette entry (plot_backend.h).
std::string hex(PLINT colour) {
  const std::array<int, 3> rgb = palette_rgb(colour);
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buffer;
}

class Svg {
 public:
  Svg(int width, int height) {
    add({"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"", std::to_string(width),
         "\" height=\"", std::to_string(height), "\" viewBox=\"0 0 ", std::to_string(width), " ",
         std::to_string(height),
         "\" font-family=\"DejaVu Sans, Verdana, sans-serif\">\n<rect width=\"100%\" "
         "height=\"100%\" fill=\"white\"/>\n"});
  }
  void add(std::initializer_list<std::string_view> parts) {
    for (const std::string_view part : parts) text_.append(part);
  }
  void line(double x0, double y0, double x1, double y1, const std::string& colour, double width) {
    add({"<line x1=\"", num(x0), "\" y1=\"", num(y0), "\" x2=\"", num(x1), "\" y2=\"", num(y1),
         "\" stroke=\"", colour, "\" stroke-width=\"", num(width), "\"/>\n"});
  }
  void circle(double x, double y, bool open, const std::string& colour) {
    add({"<circle cx=\"", num(x), "\" cy=\"", num(y), "\" r=\"", num(kMarkerRadius), "\" fill=\"",
         open ? "white" : colour, "\" stroke=\"", colour, "\" stroke-width=\"", open ? "1.6" : "1",
         "\"/>\n"});
  }
  // Text with the middle of its capitals at y (its baseline 0.36 em lower: DejaVu Sans's
  // capitals are 0.73 em high); anchor start, middle or end.
  void text(double x, double y, const char* anchor, double size, const std::string& content,
            const std::string& colour = hex(kInk), bool up = false) {
    // Turned, the baseline runs upwards 0.36 em right of x, through y.
    const std::string base_x = num(up ? x + 0.36 * size : x);
    const std::string base_y = num(up ? y : y + 0.36 * size);
    add({"<text x=\"", base_x, "\" y=\"", base_y, "\" text-anchor=\"", anchor, "\" font-size=\"",
         num(size), "\" fill=\"", colour, "\""});
    if (up) add({" transform=\"rotate(-90 ", base_x, " ", base_y, ")\""});
    add({">", content, "</text>\n"});
  }
  std::string finish() { return text_ + "</svg>\n"; }

 private:
  std::string text_;
};

std::string tick_text(const Tick& t, double size) {
  if (t.exponent.empty()) return escaped(t.label);
  return escaped(t.label) + "<tspan dy=\"" + num(-0.4 * size) + "\" font-size=\"" +
         num(0.75 * size) + "\">" + escaped(t.exponent) + "</tspan>";
}

void svg_axes(Svg& svg, const MeasuredLayout& l) {
  const Rect& p = l.plot;
  const std::string ink = hex(kInk);
  svg.add({"<rect x=\"", num(p.left), "\" y=\"", num(p.top), "\" width=\"", num(p.width()),
           "\" height=\"", num(p.height()), "\" fill=\"none\" stroke=\"", ink, "\"/>\n"});
  for (const Tick& t : l.x.ticks) {
    const double x = l.x.pixel(t.value), length = t.label.empty() ? 3.0 : 6.0;
    svg.line(x, p.bottom, x, p.bottom - length, ink, 1.0);
    svg.line(x, p.top, x, p.top + length, ink, 1.0);
    if (!t.label.empty())
      svg.text(x, p.bottom + 15.0, "middle", kTickLabelSize, tick_text(t, kTickLabelSize));
  }
  for (const Tick& t : l.y.ticks) {
    const double y = l.y.pixel(t.value), length = t.label.empty() ? 3.0 : 6.0;
    svg.line(p.left, y, p.left + length, y, ink, 1.0);
    svg.line(p.right, y, p.right - length, y, ink, 1.0);
    if (!t.label.empty())
      svg.text(p.left - 7.0, y, "end", kTickLabelSize, tick_text(t, kTickLabelSize));
  }
  for (std::size_t i = 0; i < l.title.lines.size(); ++i) {
    svg.text(l.title_x, l.title_top + (i + 0.5) * l.title.line_height(), "middle", l.title.size,
             escaped(l.title.lines[i]));
  }
  svg.text((p.left + p.right) / 2.0, l.x_label_y, "middle", l.x_label.size,
           escaped(l.x_label.lines.front()));
  svg.text(l.y_label_x, (p.top + p.bottom) / 2.0, "middle", l.y_label.size,
           escaped(l.y_label.lines.front()), ink, true);
  for (std::size_t i = 0; i < l.notes.lines.size(); ++i) {
    svg.text(8.0, l.notes_top + (i + 0.5) * l.notes.line_height(), "start", l.notes.size,
             escaped(l.notes.lines[i]), hex(kReference));
  }
}

void svg_series(Svg& svg, const MeasuredFigure& f, const MeasuredLayout& l, std::size_t i) {
  const std::string colour = hex(kSeries + l.colours[i]);
  for (const std::vector<std::size_t>& run : predicted_runs(f, l, i)) {
    std::string points;
    for (const std::size_t j : run) {
      const double x = l.x.pixel(f.x[j]), y = l.y.pixel(f.series[i].predicted[j]);
      if (run.size() == 1) {  // a lone value: a dash
        points =
            num(x - kPredictedDash) + "," + num(y) + " " + num(x + kPredictedDash) + "," + num(y);
      } else {
        points += (points.empty() ? "" : " ") + num(x) + "," + num(y);
      }
    }
    svg.add({"<polyline points=\"", points, "\" fill=\"none\" stroke=\"", colour,
             "\" stroke-width=\"1.8\"/>\n"});
  }
  for (const PointMark& m : point_marks(f, l, i)) {
    if (m.bar_top < m.bar_bottom) {
      svg.line(m.x, m.bar_top, m.x, m.bar_bottom, colour, 1.3);
      if (m.top_cap) svg.line(m.x - kBarCap, m.bar_top, m.x + kBarCap, m.bar_top, colour, 1.3);
      if (m.bottom_cap)
        svg.line(m.x - kBarCap, m.bar_bottom, m.x + kBarCap, m.bar_bottom, colour, 1.3);
    }
    svg.circle(m.x, m.y, m.open, colour);
  }
}

// A legend row's or key entry's mark from x0 over LegendLayout::kSample, centred at y.
void svg_mark(Svg& svg, const LegendRow& row, double x0, double y) {
  const double xm = x0 + LegendLayout::kSample / 2.0, x1 = x0 + LegendLayout::kSample;
  const std::string colour = hex(row.mark == LegendMark::kSeries ? kSeries + row.colour : kInk);
  if (row.has_line) svg.line(x0, y, x1, y, colour, 1.8);
  if (row.mark == LegendMark::kPoints && row.has_bar) {
    svg.line(xm, y - 6.0, xm, y + 6.0, colour, 1.3);
    svg.line(xm - kBarCap, y - 6.0, xm + kBarCap, y - 6.0, colour, 1.3);
    svg.line(xm - kBarCap, y + 6.0, xm + kBarCap, y + 6.0, colour, 1.3);
  }
  if (row.mark != LegendMark::kPredicted) svg.circle(xm, y, row.mark == LegendMark::kOpen, colour);
}

void svg_legend(Svg& svg, const MeasuredLayout& l) {
  const LegendLayout& g = l.legend;
  svg.add({"<rect x=\"", num(g.box.left), "\" y=\"", num(g.box.top), "\" width=\"",
           num(g.box.width()), "\" height=\"", num(g.box.height()), "\" fill=\"white\" stroke=\"",
           hex(kGrid), "\"/>\n"});
  for (std::size_t i = 0; i < g.rows.size(); ++i) {
    svg_mark(svg, g.rows[i], g.entry_x(i), g.entry_y(i));
    svg.text(g.entry_x(i) + LegendLayout::kSample + 6.0, g.entry_y(i), "start",
             LegendLayout::kTextSize, escaped(g.rows[i].text));
  }
  for (const KeyItem& item : l.key) {
    svg_mark(svg, item.row, item.x, item.y);
    svg.text(item.text_x(), item.y, "start", LegendLayout::kTextSize, escaped(item.row.text));
  }
}

}  // namespace

std::string plot_measured_svg(const MeasuredFigure& figure, const PlotOptions& options) {
  check_measured(figure, options);
  const MeasuredLayout l =
      layout_measured(figure, measured_title(figure, options), options.width, options.height);
  Svg svg(options.width, options.height);
  for (std::size_t i = 0; i < figure.series.size(); ++i) svg_series(svg, figure, l, i);
  svg_axes(svg, l);
  svg_legend(svg, l);
  return svg.finish();
}

}  // namespace fss
