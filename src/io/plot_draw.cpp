// The drawing helpers of the plots (plot_draw.h).
#include "io/plot_draw.h"

#include <cmath>
#include <cstdio>

#include "core/text_util.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"

namespace fss::plotting {

namespace {

// Number of characters (code points) of UTF-8 text.
std::size_t characters(const std::string& text) {
  std::size_t count = 0;
  for (const char c : text) count += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return count;
}

}  // namespace

std::string literal(std::string_view text) {
  std::string out;
  for (const char c : detail::sanitize_utf8(text)) {
    out += c;
    if (c == '#') out += '#';
  }
  return out;
}

std::string number(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

std::string ellipsize(const std::string& text, std::size_t limit) {
  std::string valid = detail::sanitize_utf8(text);
  std::size_t characters = 0, cut = valid.size();
  for (std::size_t i = 0; i < valid.size(); ++i) {
    if ((static_cast<unsigned char>(valid[i]) & 0xC0) == 0x80) continue;
    if (characters == limit - 1) cut = i;
    if (++characters > limit) return valid.substr(0, cut) + "…";
  }
  return valid;
}

void draw_title(const Canvas& canvas, const std::string& title, double right) {
  canvas.text((kLeft + canvas.width() - right) / 2.0, 22.0, 0.5, kTitleSize, kInk, title);
}

void draw_axes(const Canvas& canvas, const char* x_options, double x_tick, const char* y_options,
               const std::string& x_label, const std::string& y_label) {
  plcol0(kInk);
  plwidth(1.0);
  pllsty(1);
  canvas.text_height(kTickSize);
  plbox(x_options, x_tick, 0, y_options, 0.0, 0);
  canvas.text_height(kLabelSize);
  plmtex("b", 3.2, 0.5, 0.5, x_label.c_str());
  plmtex("l", 4.2, 0.5, 0.5, y_label.c_str());
}

void draw_dot(const Canvas& canvas, double x, double y, double radius, PLINT colour) {
  PLFLT vp[4], w[4];
  plgvpd(&vp[0], &vp[1], &vp[2], &vp[3]);
  plgvpw(&w[0], &w[1], &w[2], &w[3]);
  const double cx = (vp[0] + (x - w[0]) / (w[1] - w[0]) * (vp[1] - vp[0])) * canvas.width();
  const double cy = (vp[2] + (y - w[2]) / (w[3] - w[2]) * (vp[3] - vp[2])) * canvas.height();
  canvas.pixel_window();
  constexpr int kSides = 32;
  PLFLT px[kSides + 1], py[kSides + 1];
  for (int i = 0; i <= kSides; ++i) {
    px[i] = cx + radius * std::cos(2.0 * M_PI * i / kSides);
    py[i] = cy + radius * std::sin(2.0 * M_PI * i / kSides);
  }
  plcol0(colour);
  plfill(kSides, px, py);
  plcol0(kInk);
  plwidth(1.0);
  pllsty(1);
  plline(kSides + 1, px, py);
  plvpor(vp[0], vp[1], vp[2], vp[3]);
  plwind(w[0], w[1], w[2], w[3]);
}

void draw_legend(const Canvas& canvas, const std::vector<LegendEntry>& entries, double x, double y,
                 bool in_a_row) {
  constexpr double kRowHeight = 22.0;
  constexpr double kCharacterWidth = 9.5;  // DejaVu Sans at the tick label size, generously
  double left = x, top = y;
  for (const LegendEntry& e : entries) {
    canvas.pixel_window();
    plcol0(e.colour);
    const double sample_y = canvas.height() - top;
    if (e.line_style > 0) {
      pllsty(e.line_style);
      plwidth(e.line_width);
      pljoin(left, sample_y, left + 28.0, sample_y);
      pllsty(1);
    } else {
      draw_dot(canvas, left + 14.0, sample_y, 4.5, e.colour);
    }
    canvas.text(left + 36.0, top, 0.0, kTickSize, kInk, literal(e.text));
    if (in_a_row) {
      left += 36.0 + kCharacterWidth * characters(e.text) + 24.0;
    } else {
      top += kRowHeight;
    }
  }
}

void check_size(const PlotOptions& options) {
  for (const int side : {options.width, options.height}) {
    if (side < kPlotMinSide || side > kPlotMaxSide) {
      throw_usage_error("plot size " + std::to_string(options.width) + "x" +
                        std::to_string(options.height) +
                        " is out of range: each side must be in [" + std::to_string(kPlotMinSide) +
                        ", " + std::to_string(kPlotMaxSide) + "]");
    }
  }
}

std::vector<std::uint8_t> render_plot(const PlotOptions& options,
                                      const std::function<void(const Canvas&)>& draw) {
  check_size(options);
  std::vector<std::uint8_t> rgba(
      static_cast<std::size_t>(options.width) * static_cast<std::size_t>(options.height) * 4, 255);
  const Canvas canvas(options.width, options.height);
  render(options.width, options.height, rgba, [&] { draw(canvas); });
  return encode_png8_samples(options.width, options.height, 3, to_samples(rgba, 3),
                             PngCompression::kGraphics);
}

}  // namespace fss::plotting
