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

struct SheetPanel {
  const Image* image = nullptr;  // 1 or 3 channels, 0..255 scale
  std::string caption;
};

// The panels left to right with a gap between them, each under its caption,
// below a title line (text too long for its place is cut short with an
// ellipsis). Panels must have equal heights and channel counts; the sheet is
// gray when they are gray, RGB otherwise.
std::vector<std::uint8_t> figure_sheet_png(const std::vector<SheetPanel>& panels,
                                           const std::string& title);

// Sizes of a figure sheet (for tests and page layouts).
inline constexpr int kSheetMargin = 8;         // around the panels and between them
inline constexpr int kSheetHeaderHeight = 52;  // title and caption lines above the panels

}  // namespace fss
