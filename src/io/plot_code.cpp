// The figures of a code (fss/io/plot.h): its gain function, |K| against the
// snapshot's, and |K| of several codes overlaid.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/text_util.h"
#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/simulate.h"
#include "io/plot_backend.h"
#include "io/plot_draw.h"

namespace fss {

using plotting::Canvas;
using plotting::check_size;
using plotting::draw_axes;
using plotting::draw_dot;
using plotting::draw_legend;
using plotting::draw_title;
using plotting::ellipsize;
using plotting::kBottom;
using plotting::kLabelSize;
using plotting::kLeft;
using plotting::kMaxSeries;
using plotting::kRight;
using plotting::kTickSize;
using plotting::LegendEntry;
using plotting::literal;
using plotting::number;
using plotting::render_plot;
using enum plotting::Colour;

namespace {

// The simulator's check of a code (check_code_for_mode, numerical: any real
// gains): no gains, too many, only zeros, or a scale sums and |K| overflow.
void check_gains(const std::vector<double>& gains, const std::string& name) {
  check_code_for_mode(ShutterCode{name, gains}, ShutterMode::kNumerical);
}

void check_motion(double velocity, double dt) {
  const std::string rule =
      !std::isfinite(velocity) ? "velocity " + velocity_rule(velocity) : "dt " + scale_rule(dt);
  if (rule.size() > 3) {
    throw_usage_error("cannot plot |K| at velocity " + format_exact(velocity) + ", dt " +
                      format_exact(dt) + ": " + rule);
  }
}

// Frequencies sampled for a spectrum plot: two per pixel column.
std::vector<double> frequencies(int width) {
  const int n = 2 * width + 1;
  std::vector<double> xi(n);
  for (int j = 0; j < n; ++j) xi[j] = -M_PI + 2.0 * M_PI * j / (n - 1);
  xi.back() = M_PI;
  return xi;
}

std::vector<double> abs_k(const std::vector<double>& gains, double velocity, double dt,
                          const std::vector<double>& xi) {
  std::vector<double> magnitude(xi.size());
  for (std::size_t j = 0; j < xi.size(); ++j) {
    magnitude[j] = std::abs(transfer_function(gains, velocity, dt, xi[j]));
  }
  return magnitude;
}

std::string motion_text(double velocity, double dt) {
  return "v = " + number("%g", velocity) + ", dt = " + number("%g", dt);
}

// The x axis of a spectrum: ticks and labels at multiples of pi / 2.
void draw_frequency_labels(const Canvas& canvas) {
  canvas.text_height(kTickSize);
  plcol0(kInk);
  const char* labels[] = {"−π", "−π/2", "0", "π/2", "π"};
  for (int i = 0; i < 5; ++i) plmtex("b", 1.6, i / 4.0, 0.5, labels[i]);
}

// Light vertical lines at multiples of pi / 2.
void draw_frequency_grid(double y_min, double y_max) {
  plcol0(kGrid);
  plwidth(0.5);
  pllsty(1);
  for (int i = -1; i <= 1; ++i) pljoin(i * M_PI / 2.0, y_min, i * M_PI / 2.0, y_max);
}

// log10 `value` on a log axis starting at `y_low` (smaller values at its edge).
double log_on_axis(double value, double y_low) {
  return std::log10(std::max(value, std::pow(10.0, y_low)));
}

// Curves of |K| on a logarithmic axis (both |K| plots): each value becomes
// log10 |K|; the axis runs from the decade at or below the smallest value
// above 1e-4 `top` (`top` the largest value; smaller ones, zeros, are drawn at
// the bottom edge) to 0.08 above log10 `top`, at least one decade high, so
// that two decades at least are labelled.
std::pair<double, double> to_log_axis(std::vector<std::vector<double>>& curves, double top) {
  double bottom = top;
  for (const auto& curve : curves) {
    for (const double value : curve) {
      if (value > top * 1e-4) bottom = std::min(bottom, value);
    }
  }
  const double y_low = std::floor(std::log10(bottom));
  for (auto& curve : curves) {
    for (double& value : curve) value = log_on_axis(value, y_low);
  }
  return {y_low, std::max(std::log10(top) + 0.08, y_low + 1.0)};
}

}  // namespace

std::vector<std::uint8_t> plot_code_png(const std::vector<double>& gains, const std::string& name,
                                        const PlotOptions& options) {
  check_gains(gains, name);
  const int length = static_cast<int>(gains.size());
  const auto [low_it, high_it] = std::minmax_element(gains.begin(), gains.end());
  double low = std::min(0.0, *low_it), high = std::max(0.0, *high_it);
  const double span = high > low ? high - low : 1.0;
  low -= 0.08 * span;
  high += 0.08 * span;
  const double pad = std::max(0.5, 0.02 * length);
  const std::string title = options.title.empty()
                                ? "Gain function α(t) of " +
                                      literal(ellipsize(std::string(detail::base_name(name)), 24)) +
                                      ", L = " + std::to_string(length)
                                : literal(options.title);

  // The step curve from (0, 0) up to alpha_0, across every slot, and down to
  // (L, 0); closed along the zero line it is also the filled area.
  std::vector<PLFLT> x, y;
  x.reserve(2 * length + 2);
  y.reserve(2 * length + 2);
  x.push_back(0.0);
  y.push_back(0.0);
  for (int k = 0; k < length; ++k) {
    x.push_back(k);
    y.push_back(gains[k]);
    x.push_back(k + 1);
    y.push_back(gains[k]);
  }
  x.push_back(length);
  y.push_back(0.0);

  return render_plot(options, [&](const Canvas& canvas) {
    draw_title(canvas, title);
    canvas.viewport(kLeft, kRight, 40.0, kBottom);
    plwind(-pad, length + pad, low, high);
    plcol0(kCodeFill);
    plfill(static_cast<PLINT>(x.size()), x.data(), y.data());
    plcol0(kGrid);
    plwidth(1.0);
    pljoin(-pad, 0.0, length + pad, 0.0);
    plcol0(kCode);
    plwidth(2.0);
    plline(static_cast<PLINT>(x.size()), x.data(), y.data());
    draw_axes(canvas, "bcnst", 0.0, "bcnstv", "slot k   (α(t) = α#dk#u for k dt ≤ t < (k + 1) dt)",
              "gain α#dk#u");
  });
}

std::vector<std::uint8_t> plot_spectrum_png(const std::vector<double>& gains,
                                            const std::string& name, double velocity, double dt,
                                            const KernelAnalysis& kernel,
                                            const PlotOptions& options) {
  check_gains(gains, name);
  check_motion(velocity, dt);
  check_size(options);
  const std::vector<double> xi = frequencies(options.width);
  // The code's curve and the snapshot's, with the minimum of |K| as a third
  // "curve" of one point so that the axis reaches down to it.
  std::vector<std::vector<double>> curves = {
      abs_k(gains, velocity, dt, xi), abs_k({1.0}, velocity, dt, xi), {kernel.min_abs}};
  double top = 0.0;
  for (const auto& curve : curves) {
    top = std::max(top, *std::max_element(curve.begin(), curve.end()));
  }
  if (!(top > 0.0)) top = 1.0;
  const std::pair<double, double> y_range = to_log_axis(curves, top);
  const double y_low = y_range.first, y_high = y_range.second;
  const std::vector<double>& code = curves[0];
  const std::vector<double>& snapshot = curves[1];
  const double minimum_y = curves[2][0];
  const std::string short_name(detail::base_name(name));
  const std::string title =
      options.title.empty()
          ? "|K(ξ)| of " + literal(ellipsize(short_name, 24)) + ", " + motion_text(velocity, dt)
          : literal(options.title);
  const std::string where = kernel.min_abs_xi > 0.0 ? "±" + number("%.4g", kernel.min_abs_xi)
                                                    : number("%.4g", kernel.min_abs_xi);
  const std::string note =
      kernel.invertible ? "minimum |K| = " + number("%.4g", kernel.min_abs) + " at ξ = " + where
                        : "NOT INVERTIBLE: |K| = 0 at ξ = " + where + " (min |K| " +
                              number("%.2g", kernel.min_abs) + ")";

  return render_plot(options, [&](const Canvas& canvas) {
    draw_title(canvas, title);
    canvas.text((kLeft + canvas.width() - kRight) / 2.0, 44.0, 0.5, kLabelSize,
                kernel.invertible ? kInk : kWarning, note);
    canvas.viewport(kLeft, kRight, 88.0, kBottom);
    plwind(-M_PI, M_PI, y_low, y_high);
    draw_frequency_grid(y_low, y_high);
    const auto n = static_cast<PLINT>(xi.size());
    // The reference on top, so that it stays visible where the curves meet.
    plcol0(kCode);
    plwidth(2.0);
    plline(n, xi.data(), code.data());
    plcol0(kReference);
    plwidth(1.5);
    pllsty(2);
    plline(n, xi.data(), snapshot.data());
    pllsty(1);
    draw_dot(canvas, kernel.min_abs_xi, minimum_y, 4.5, kMarker);
    if (kernel.min_abs_xi > 0.0) draw_dot(canvas, -kernel.min_abs_xi, minimum_y, 4.5, kMarker);
    draw_axes(canvas, "bcst", M_PI / 2.0, "bcnstvl", "ξ (radians per pixel)",
              "|K(ξ)|  (log scale)");
    draw_frequency_labels(canvas);
    draw_legend(canvas,
                {{ellipsize(short_name, 16), kCode, 1, 2.0},
                 {"snapshot", kReference, 2, 1.5},
                 {"minimum of |K|", kMarker, 0, 0.0}},
                kLeft + 8.0, 68.0, true);
  });
}

namespace {

// |K| of each code of an overlay at the frequencies `xi`, its legend entry,
// and the largest value of all.
struct OverlayCurves {
  std::vector<std::vector<double>> curves;
  std::vector<LegendEntry> legend;
  double top = 0.0;
};

OverlayCurves overlay_curves(const std::vector<ShutterCode>& codes, double velocity, double dt,
                             const std::vector<double>& xi) {
  OverlayCurves o;
  int series = 0;
  for (const ShutterCode& code : codes) {
    o.curves.push_back(abs_k(code.gains, velocity, dt, xi));
    for (const double value : o.curves.back()) o.top = std::max(o.top, value);
    const KernelAnalysis kernel = analyze_kernel(code.gains, velocity, dt);
    std::string text = ellipsize(std::string(detail::base_name(code.name)), 14);
    text += kernel.invertible ? ", min " + number("%.3g", kernel.min_abs) : ", has zeros";
    // The snapshot is the dashed reference, as in the spectrum plot.
    const bool snapshot = code.name == "snapshot";
    o.legend.push_back({text, snapshot ? kInk : static_cast<PLINT>(kSeries + series++),
                        snapshot ? 2 : 1, snapshot ? 1.5 : 1.8});
  }
  if (!(o.top > 0.0)) o.top = 1.0;
  return o;
}

// The y range of an overlay; on a log scale, the curves become log10 |K|
// (to_log_axis).
std::pair<double, double> overlay_y_range(OverlayCurves& o, bool log_scale) {
  if (!log_scale) return {0.0, o.top * 1.06};
  return to_log_axis(o.curves, o.top);
}

}  // namespace

std::vector<std::uint8_t> plot_spectra_overlay_png(const std::vector<ShutterCode>& codes,
                                                   double velocity, double dt, bool log_scale,
                                                   const PlotOptions& options) {
  if (codes.empty() || static_cast<int>(codes.size()) > kMaxSeries) {
    throw_usage_error("an overlay of spectra takes 1 to " + std::to_string(kMaxSeries) +
                      " codes, got " + std::to_string(codes.size()));
  }
  for (const ShutterCode& code : codes) check_gains(code.gains, code.name);
  check_motion(velocity, dt);
  check_size(options);
  const std::vector<double> xi = frequencies(options.width);
  OverlayCurves overlay = overlay_curves(codes, velocity, dt, xi);
  // Named values, not a structured binding: clang 14 cannot capture one.
  const std::pair<double, double> y_range = overlay_y_range(overlay, log_scale);
  const double y_low = y_range.first, y_high = y_range.second;
  const std::string title = options.title.empty() ? "|K(ξ)| of " + std::to_string(codes.size()) +
                                                        " codes, " + motion_text(velocity, dt)
                                                  : literal(options.title);

  return render_plot(options, [&](const Canvas& canvas) {
    const double legend_width = std::min(220.0, 0.35 * canvas.width());
    draw_title(canvas, title, kRight + legend_width);
    canvas.viewport(kLeft, kRight + legend_width, 40.0, kBottom);
    plwind(-M_PI, M_PI, y_low, y_high);
    draw_frequency_grid(y_low, y_high);
    const auto n = static_cast<PLINT>(xi.size());
    for (std::size_t i = 0; i < overlay.curves.size(); ++i) {
      plcol0(overlay.legend[i].colour);
      pllsty(overlay.legend[i].line_style);
      plwidth(overlay.legend[i].line_width);
      plline(n, xi.data(), overlay.curves[i].data());
    }
    pllsty(1);
    draw_axes(canvas, "bcst", M_PI / 2.0, log_scale ? "bcnstvl" : "bcnstv", "ξ (radians per pixel)",
              log_scale ? "|K(ξ)|  (log scale)" : "|K(ξ)|");
    draw_frequency_labels(canvas);
    draw_legend(canvas, overlay.legend, canvas.width() - kRight - legend_width + 16.0, 52.0, false);
  });
}

}  // namespace fss
