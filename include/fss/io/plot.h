// Pictures of a run, rendered in the process with PLplot (cairo driver) into
// PNG bytes in memory: the gain function of a code, |K| of one code against
// the snapshot, |K| of several codes overlaid, and figure sheets that put a
// run's images side by side. Conventions: image.h.
//
// All PLplot calls of the process go through one mutex (PLplot keeps global
// state), so these functions may be called from any thread. They print
// nothing; a PLplot failure is a runtime fss::Error. Text taken from the
// caller (titles, code names, captions) is drawn literally.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"

namespace fss {

inline constexpr int kPlotWidth = 640;
inline constexpr int kPlotHeight = 400;
// Accepted plot sides, in pixels.
inline constexpr int kPlotMinSide = 160;
inline constexpr int kPlotMaxSide = 8192;

struct PlotOptions {
  int width = kPlotWidth;
  int height = kPlotHeight;
  std::string title;  // empty: a title made from the data
};

// The gain function alpha(t) = alpha_k on [k dt, (k + 1) dt) as steps over
// the exposure: slot k on the x axis, gain on the y axis (negative gains
// below the zero line). `name` labels the code in the default title.
std::vector<std::uint8_t> plot_code_png(const std::vector<double>& gains, const std::string& name,
                                        const PlotOptions& options = {});

// |K(xi)| for xi in [-pi, pi] at `velocity` and `dt`, the snapshot's |K| at
// the same velocity dashed, and the minimum of |K| from `kernel` (the
// analyze_kernel result for the same gains, velocity and dt) marked; a code
// that is not invertible is said so in red.
std::vector<std::uint8_t> plot_spectrum_png(const std::vector<double>& gains,
                                            const std::string& name, double velocity, double dt,
                                            const KernelAnalysis& kernel,
                                            const PlotOptions& options = {});

// |K(xi)| of every code of `codes` on one plot (at most 8 codes), on a
// logarithmic axis when `log_scale` (zeros are drawn at the bottom edge).
std::vector<std::uint8_t> plot_spectra_overlay_png(const std::vector<ShutterCode>& codes,
                                                   double velocity, double dt,
                                                   bool log_scale = true,
                                                   const PlotOptions& options = {});

// One curve of plot_curves_png.
struct CurveSeries {
  std::string name;       // in the legend
  std::vector<double> y;  // one value per x; NaN or infinite values leave a gap
  bool dashed = false;    // dashed line (a prediction, say)
  bool markers = false;   // a marker at every point (measurements, say)
};

// Curves over shared x values (increasing), with axes labelled `x_label`
// and `y_label`, and a legend (at most 8 curves).
std::vector<std::uint8_t> plot_curves_png(const std::vector<double>& x,
                                          const std::vector<CurveSeries>& series,
                                          const std::string& x_label, const std::string& y_label,
                                          const PlotOptions& options = {});

// One curve of plot_error_bar_curves_png: values with a symmetric error.
struct ErrorBarSeries {
  std::string name;           // in the legend
  std::vector<double> y;      // one value per x; NaN or infinite values leave a gap
  std::vector<double> error;  // half-height of each bar (0 or NaN: no bar)
};

// Curves over shared x values (increasing; > 0 when `log_x`), each with a
// marker and an error bar y +/- error at every point, a logarithmic x axis
// when `log_x`, and a legend (at most 8 curves).
std::vector<std::uint8_t> plot_error_bar_curves_png(const std::vector<double>& x,
                                                    const std::vector<ErrorBarSeries>& series,
                                                    const std::string& x_label,
                                                    const std::string& y_label, bool log_x,
                                                    const PlotOptions& options = {});

// What the gray levels of a sheet panel stand for: gray 0 is `black`, 255 is
// `white`, linearly in between; drawn as a labelled gray bar under the panel.
struct SheetScale {
  double black = 0.0;
  double white = 255.0;
  std::string unit;  // under the bar: "gray levels of ground truth − restored"
};

// One series of a figure of measurements and their prediction: points with
// error bars and the predicted curve, in one colour.
struct MeasuredSeries {
  std::string name;               // in the legend
  std::vector<double> measured;   // one value per x; NaN or infinite: no point
  std::vector<double> error;      // half-height of each bar (empty, 0 or NaN: no bar)
  std::vector<double> predicted;  // one value per x (empty: no curve); NaN or inf: a gap
  std::vector<bool> open;         // an open marker at that x (empty: every marker filled)
  int colour = -1;                // 0 .. 7 of the series' palette; -1: the series' index
};

enum class AxisScale { kAuto, kLinear, kLog };

// A figure of MeasuredSeries over shared x values (plot_measured_png/svg).
// The legend has one entry per series, then a key of the marks in ink:
// `points_key` beside a marker with its bar, `predicted_key` beside a line
// (when a series has a prediction), `open_key` beside an open marker (when a
// point is open), under the plot. The legend sits in a corner of the plot
// area that no point, bar or curve reaches, else to the right of it (under
// it, in columns, when it is wide); on a picture too small for either, over
// the plot area's top right corner. `notes` are lines under the key; on a
// small picture the key and the notes are left out.
struct MeasuredFigure {
  std::vector<double> x;               // finite and increasing; > 0 when log_x
  std::vector<MeasuredSeries> series;  // 1 to 8
  std::string x_label;
  std::string y_label;
  bool log_x = false;
  // kAuto: logarithmic when every value is > 0 and they span a decade or more, else linear
  // from 0 (from below 0 when a value is negative).
  AxisScale y_scale = AxisScale::kAuto;
  std::string points_key = "measured";
  std::string predicted_key = "predicted";
  std::string open_key;
  std::vector<std::string> notes;
};

// The figure as PNG bytes, and as an SVG document of the same layout. The
// title (options.title; "Y against X" when empty) is kept on one line, else
// wrapped onto two, in a smaller font if need be, cut short in its middle
// only past that. On a log axis every power of ten is labelled 10^k, and 2
// and 5 times them when fewer than 3 would show (else plain steps). A usage
// fss::Error for data it cannot draw (no x, x not increasing or <= 0 on a log
// axis, lengths unlike x's, 0 or more than 8 series, no point).
std::vector<std::uint8_t> plot_measured_png(const MeasuredFigure& figure,
                                            const PlotOptions& options = {});
std::string plot_measured_svg(const MeasuredFigure& figure, const PlotOptions& options = {});

struct SheetPanel {
  const Image* image = nullptr;  // 1 or 3 channels, 0..255 scale
  std::string caption;
  std::optional<SheetScale> scale = std::nullopt;  // none: no bar
};

// The panels left to right with a gap between them, each under its caption,
// below a title line (text too long for its place is cut short with an
// ellipsis), and a gray bar with its values under each panel that has a scale.
// Panels must have equal heights and channel counts; the sheet is gray when
// they are gray, RGB otherwise.
std::vector<std::uint8_t> figure_sheet_png(const std::vector<SheetPanel>& panels,
                                           const std::string& title);

// Sizes of a figure sheet (for tests and page layouts).
inline constexpr int kSheetMargin = 8;         // around the panels and between them
inline constexpr int kSheetHeaderHeight = 52;  // title and caption lines above the panels
inline constexpr int kSheetScaleHeight = 58;   // below the panels when a panel has a scale

}  // namespace fss
