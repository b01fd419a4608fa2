// The figures of curves (fss/io/plot.h): curves over shared x values, and
// curves with error bars.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "io/plot_backend.h"
#include "io/plot_draw.h"

namespace fss {

using plotting::Canvas;
using plotting::draw_axes;
using plotting::draw_legend;
using plotting::draw_title;
using plotting::ellipsize;
using plotting::kBottom;
using plotting::kLeft;
using plotting::kMaxSeries;
using plotting::kRight;
using plotting::LegendEntry;
using plotting::literal;
using plotting::render_plot;
using enum plotting::Colour;

namespace {

// The title of a plot of curves: the one asked for, or "Y against X".
std::string curves_title(const PlotOptions& options, const std::string& x_label,
                         const std::string& y_label) {
  return options.title.empty() ? literal(y_label) + " against " + literal(x_label)
                               : literal(options.title);
}

void check_curves(const std::vector<double>& x, const std::vector<CurveSeries>& series) {
  if (x.empty()) throw_usage_error("a curve plot needs at least one x value");
  if (series.empty() || static_cast<int>(series.size()) > kMaxSeries) {
    throw_usage_error("a curve plot takes 1 to " + std::to_string(kMaxSeries) + " curves, got " +
                      std::to_string(series.size()));
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || (i > 0 && !(x[i] > x[i - 1]))) {
      throw_usage_error("the x values of a curve plot must be finite and increasing");
    }
  }
  for (const CurveSeries& curve : series) {
    if (curve.y.size() != x.size()) {
      throw_usage_error("curve '" + curve.name + "' has " + std::to_string(curve.y.size()) +
                        " values for " + std::to_string(x.size()) + " x values");
    }
  }
}

// The y range of a curve plot: the finite values with a margin, 0 staying
// the floor of non-negative curves.
std::pair<double, double> curves_y_range(const std::vector<CurveSeries>& series) {
  double low = HUGE_VAL, high = -HUGE_VAL;
  for (const CurveSeries& curve : series) {
    for (const double v : curve.y) {
      if (std::isfinite(v)) {
        low = std::min(low, v);
        high = std::max(high, v);
      }
    }
  }
  if (!(low <= high)) low = 0.0, high = 1.0;  // no finite value: an empty frame
  const double pad = high > low ? 0.08 * (high - low) : std::max(1.0, std::abs(high)) * 0.1;
  const double y_low = low >= 0.0 ? std::max(0.0, low - pad) : low - pad;
  return {y_low, high + pad};
}

// One curve in the current window: runs of finite values, each a polyline,
// gaps where a value is missing; then its markers if it has them.
void draw_curve(const std::vector<double>& x, const CurveSeries& curve, const LegendEntry& style) {
  plcol0(style.colour);
  pllsty(style.line_style);
  plwidth(style.line_width);
  std::vector<double> run_x, run_y;
  auto flush = [&] {
    if (run_x.size() > 1) plline(static_cast<PLINT>(run_x.size()), run_x.data(), run_y.data());
    run_x.clear();
    run_y.clear();
  };
  for (std::size_t j = 0; j < x.size(); ++j) {
    if (std::isfinite(curve.y[j])) {
      run_x.push_back(x[j]);
      run_y.push_back(curve.y[j]);
    } else {
      flush();
    }
  }
  flush();
  if (!curve.markers) return;
  pllsty(1);
  plssym(0.0, 1.6);  // markers 1.6 times the default size
  for (std::size_t j = 0; j < x.size(); ++j) {
    if (!std::isfinite(curve.y[j])) continue;
    double px = x[j], py = curve.y[j];
    plpoin(1, &px, &py, 17);  // filled circle
  }
}

// The series as plain curves (for the checks and the y range), with the
// error bars' ends as two more value lists each.
std::vector<CurveSeries> error_bar_extent(const std::vector<ErrorBarSeries>& series) {
  std::vector<CurveSeries> extent;
  for (const ErrorBarSeries& s : series) {
    CurveSeries low{s.name, s.y}, high{s.name, s.y};
    for (std::size_t j = 0; j < s.y.size() && j < s.error.size(); ++j) {
      if (std::isfinite(s.error[j])) {
        low.y[j] -= s.error[j];
        high.y[j] += s.error[j];
      }
    }
    extent.push_back(low);
    extent.push_back(high);
  }
  return extent;
}

void draw_error_bars(const std::vector<double>& x, const ErrorBarSeries& s, PLINT colour) {
  plcol0(colour);
  pllsty(1);
  plwidth(1.2);
  for (std::size_t j = 0; j < x.size(); ++j) {
    if (!std::isfinite(s.y[j]) || !std::isfinite(s.error[j]) || !(s.error[j] > 0.0)) continue;
    PLFLT px = x[j], low = s.y[j] - s.error[j], high = s.y[j] + s.error[j];
    plerry(1, &px, &low, &high);
  }
}

}  // namespace

std::vector<std::uint8_t> plot_curves_png(const std::vector<double>& x,
                                          const std::vector<CurveSeries>& series,
                                          const std::string& x_label, const std::string& y_label,
                                          const PlotOptions& options) {
  check_curves(x, series);
  const std::pair<double, double> y_range = curves_y_range(series);
  const double y_low = y_range.first, y_high = y_range.second;
  const double x_pad = x.size() > 1 ? 0.03 * (x.back() - x.front()) : 0.5;
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) {
    legend.push_back({ellipsize(series[i].name, 40), static_cast<PLINT>(kSeries + i),
                      series[i].dashed ? 2 : 1, 1.8});
  }
  const std::string title = curves_title(options, x_label, y_label);
  return render_plot(options, [&](const Canvas& canvas) {
    draw_title(canvas, title);
    canvas.viewport(kLeft, kRight, 40.0, kBottom);
    plwind(x.front() - x_pad, x.back() + x_pad, y_low, y_high);
    for (std::size_t i = 0; i < series.size(); ++i) draw_curve(x, series[i], legend[i]);
    pllsty(1);
    draw_axes(canvas, "bcnst", 0.0, "bcnstv", literal(x_label), literal(y_label));
    draw_legend(canvas, legend, kLeft + 12.0, 52.0, false);
  });
}

std::vector<std::uint8_t> plot_error_bar_curves_png(const std::vector<double>& x,
                                                    const std::vector<ErrorBarSeries>& series,
                                                    const std::string& x_label,
                                                    const std::string& y_label, bool log_x,
                                                    const PlotOptions& options) {
  std::vector<CurveSeries> curves;
  for (const ErrorBarSeries& s : series) {
    if (s.error.size() != s.y.size()) {
      throw_usage_error("curve '" + s.name + "' has " + std::to_string(s.error.size()) +
                        " errors for " + std::to_string(s.y.size()) + " values");
    }
    curves.push_back({s.name, s.y, false, true});
  }
  check_curves(x, curves);
  if (log_x && !(x.front() > 0.0)) throw_usage_error("a logarithmic x axis needs x values > 0");
  // PLplot's logarithmic axes take log10 of the coordinates.
  std::vector<double> px = x;
  if (log_x) {
    for (double& v : px) v = std::log10(v);
  }
  const std::pair<double, double> y_range = curves_y_range(error_bar_extent(series));
  const double x_pad = px.size() > 1 ? 0.04 * (px.back() - px.front()) : 0.5;
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) {
    legend.push_back({ellipsize(series[i].name, 40), static_cast<PLINT>(kSeries + i), 1, 1.8});
  }
  const std::string title = curves_title(options, x_label, y_label);
  return render_plot(options, [&](const Canvas& canvas) {
    draw_title(canvas, title);
    canvas.viewport(kLeft, kRight, 40.0, kBottom);
    plwind(px.front() - x_pad, px.back() + x_pad, y_range.first, y_range.second);
    for (std::size_t i = 0; i < series.size(); ++i) {
      draw_curve(px, curves[i], legend[i]);
      draw_error_bars(px, series[i], legend[i].colour);
    }
    pllsty(1);
    draw_axes(canvas, log_x ? "bcnstl" : "bcnst", 0.0, "bcnstv", literal(x_label),
              literal(y_label));
    draw_legend(canvas, legend, kLeft + 12.0, 52.0, false);
  });
}

}  // namespace fss
