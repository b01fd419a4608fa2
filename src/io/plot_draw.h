// Private to the plots (src/io/plot_*.cpp): drawing helpers shared by the
// figures, and the rendering of a figure of PlotOptions into PNG bytes.
// Sizes and positions are in pixels of the picture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fss/io/plot.h"
#include "io/plot_backend.h"
#include "io/plplot_api.h"

namespace fss::plotting {

// Literal text for PLplot: valid UTF-8 and its escape character doubled.
std::string literal(std::string_view text);

// `value` printed by snprintf with `format`.
std::string number(const char* format, double value);

// At most `limit` characters of `text`, an ellipsis replacing the rest.
std::string ellipsize(const std::string& text, std::size_t limit);

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height) {}

  void text_height(double pixels) const { plschr(pixels / kPixelsPerMm, 1.0); }

  // Pixel coordinates (y up) on the whole picture.
  void pixel_window() const {
    plvpor(0.0, 1.0, 0.0, 1.0);
    plwind(0.0, width_, 0.0, height_);
  }

  // PLplot text (escapes interpreted; see literal()) vertically centred at
  // `y` pixels from the top; `just` 0 left, 0.5 centre, 1 right of x.
  void text(double x, double y, double just, double size, PLINT colour,
            const std::string& content) const {
    pixel_window();
    text_height(size);
    plcol0(colour);
    plptex(x, height_ - y, 1.0, 0.0, just, content.c_str());
  }

  // The plot area, inset from the edges by the given margins.
  void viewport(double left, double right, double top, double bottom) const {
    plvpor(left / width_, 1.0 - right / width_, bottom / height_, 1.0 - top / height_);
  }

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_;
  int height_;
};

// Margins of a plot area, in pixels.
inline constexpr double kLeft = 70.0;
inline constexpr double kRight = 22.0;
inline constexpr double kBottom = 58.0;
inline constexpr double kTitleSize = 15.0;
inline constexpr double kLabelSize = 13.0;
inline constexpr double kTickSize = 12.0;

// The title centred over the plot area, which ends `right` pixels from the
// right edge.
void draw_title(const Canvas& canvas, const std::string& title, double right = kRight);

// Frame, ticks and tick labels of the current window, and the axis labels
// (PLplot text).
void draw_axes(const Canvas& canvas, const char* x_options, double x_tick, const char* y_options,
               const std::string& x_label, const std::string& y_label);

// A dot of `radius` pixels centred on the world point (x, y) of the current
// viewport and window, which are kept.
void draw_dot(const Canvas& canvas, double x, double y, double radius, PLINT colour);

struct LegendEntry {
  std::string text;
  PLINT colour;
  PLINT line_style;  // 0: a dot instead of a line
  double line_width;
};

// Legend entries from (x, y) pixels, in a row or one under the other: a
// 28-pixel sample of the line (or a dot), then the text.
void draw_legend(const Canvas& canvas, const std::vector<LegendEntry>& entries, double x, double y,
                 bool in_a_row);

// A usage fss::Error unless both sides of the plot are in [kPlotMinSide,
// kPlotMaxSide].
void check_size(const PlotOptions& options);

// The figure `draw` draws on a white canvas of the options' size, as RGB PNG
// bytes.
std::vector<std::uint8_t> render_plot(const PlotOptions& options,
                                      const std::function<void(const Canvas&)>& draw);

}  // namespace fss::plotting
