#include "fss/io/plot.h"

#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "core/stderr_capture.h"
#include "core/text_util.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/simulate.h"

namespace fss {
namespace {

// ---------------------------------------------------------------------------
// PLplot session: one stream per picture, drawn by the memcairo device over a
// caller-owned RGBA buffer, all of it under one process-wide mutex.

std::mutex g_plplot_mutex;
std::string* g_plplot_messages = nullptr;  // guarded by g_plplot_mutex

// PLplot reports recoverable errors through this handler (instead of printing
// them on stderr); they are turned into an fss::Error after the picture.
void collect_plplot_message(PLCHAR_VECTOR message) {
  if (g_plplot_messages == nullptr) return;
  if (!g_plplot_messages->empty()) *g_plplot_messages += "; ";
  *g_plplot_messages += message;
}

// PLplot calls exit() after this handler returns: throw instead, so that a
// fatal PLplot error becomes an fss::Error and not the end of the process
// (the exception unwinds through PLplot's C frames, which Debian builds with
// unwind tables). The stream is then ended by render().
int refuse_plplot_exit(PLCHAR_VECTOR message) {
  throw Error(ErrorKind::kRuntime, std::string("PLplot failed: ") + message);
}

bool memcairo_available() {
  constexpr int kCapacity = 256;
  PLCHAR_VECTOR menus[kCapacity];
  PLCHAR_VECTOR names[kCapacity];
  PLCHAR_VECTOR* menu_list = menus;
  PLCHAR_VECTOR* name_list = names;
  int count = kCapacity;
  plgDevs(&menu_list, &name_list, &count);
  for (int i = 0; i < count; ++i) {
    if (name_list[i] != nullptr && std::strcmp(name_list[i], "memcairo") == 0) return true;
  }
  return false;
}

// Colour map 0 of every picture.
enum Colour : PLINT {
  kBackground = 0,
  kInk = 1,        // axes, labels, text
  kGrid = 2,       // zero line and grid
  kCode = 3,       // the code's curve
  kCodeFill = 4,   // area under the gain function
  kReference = 5,  // the snapshot
  kMarker = 6,     // the minimum of |K|
  kWarning = 7,    // "not invertible"
  kSeries = 8,     // 8 .. 15: overlaid codes
};
constexpr int kPaletteSize = 16;
constexpr int kMaxSeries = kPaletteSize - kSeries;
constexpr PLINT kPalette[kPaletteSize][3] = {
    {255, 255, 255}, {34, 34, 34},   {175, 175, 175}, {31, 92, 170},   // background .. code
    {196, 214, 238}, {90, 90, 90},   {200, 30, 30},   {190, 20, 20},   // fill .. warning
    {31, 92, 170},   {214, 120, 20}, {40, 150, 60},   {150, 60, 170},  // series
    {20, 160, 180},  {200, 30, 30},  {140, 110, 40},  {110, 110, 110},
};

// The cairo driver draws at 72 dots per inch; PLplot sizes text in mm.
constexpr double kPixelsPerMm = 72.0 / 25.4;

// What the libraries under PLplot printed during a picture, as one line:
// its non-empty lines joined by "; ", PLplot's "*** PLPLOT WARNING ***"
// banners left out, control characters escaped, at most about 400 bytes.
std::string library_output_line(std::string_view text) {
  std::string line;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find('\n'), text.size());
    std::string_view part = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    while (!part.empty() && (part.back() == '\r' || part.back() == ' ')) part.remove_suffix(1);
    if (part.empty() || part.find("*** PLPLOT") == 0) continue;
    if (!line.empty()) line += "; ";
    line += part;
  }
  constexpr std::size_t kMaxBytes = 400;
  if (line.size() > kMaxBytes) line = line.substr(0, kMaxBytes) + "...";
  return escape_control_characters(line);
}

// One PLplot stream drawing over `rgba` until the end of the scope.
class PlplotStream {
 public:
  PlplotStream(int width, int height, std::vector<std::uint8_t>& rgba) {
    plsabort(collect_plplot_message);
    plsexit(refuse_plplot_exit);
    plgstrm(&previous_);
    PLINT stream = 0;
    plmkstrm(&stream);
    if (stream < 0) throw_runtime_error("PLplot has no free stream");
    plsdev("memcairo");
    plsmema(width, height, rgba.data());
    plspause(0);
    plscmap0n(kPaletteSize);
    for (int i = 0; i < kPaletteSize; ++i) {
      plscol0(i, kPalette[i][0], kPalette[i][1], kPalette[i][2]);
    }
    plinit();
    pladv(0);
  }
  ~PlplotStream() {
    plend1();
    plsstrm(previous_);
  }
  PlplotStream(const PlplotStream&) = delete;
  PlplotStream& operator=(const PlplotStream&) = delete;

 private:
  PLINT previous_ = 0;
};

// Draws `draw` over `rgba` (width x height RGBA, rows top down). PLplot's
// recoverable errors and anything a library prints on stderr meanwhile
// (PLplot's warnings, GLib's) fail the picture with that text, and never
// reach stderr.
void render(int width, int height, std::vector<std::uint8_t>& rgba,
            const std::function<void()>& draw) {
  std::lock_guard<std::mutex> lock(g_plplot_mutex);
  static const bool available = memcairo_available();
  if (!available) {
    throw_runtime_error(
        "cannot draw plots: PLplot's memcairo device is missing (install the Debian package "
        "plplot-driver-cairo, or run with --no-plots)");
  }
  std::string messages;
  struct Collect {
    explicit Collect(std::string* messages) { g_plplot_messages = messages; }
    ~Collect() { g_plplot_messages = nullptr; }
    Collect(const Collect&) = delete;
    Collect& operator=(const Collect&) = delete;
  } collect(&messages);
  detail::StderrCapture capture;
  {
    const PlplotStream stream(width, height, rgba);
    draw();
  }
  const std::string printed = library_output_line(capture.Finish());
  if (!printed.empty()) messages += (messages.empty() ? "" : "; ") + printed;
  if (!messages.empty()) throw_runtime_error("PLplot: " + messages);
}

// The RGBA buffer as interleaved RGB, or gray, 8-bit samples; gray is the
// rounded mean of red, green and blue: round(s / 3) = (s + 1) / 3 for s >= 0.
std::vector<std::uint8_t> to_samples(const std::vector<std::uint8_t>& rgba, int channels) {
  const std::size_t pixels = rgba.size() / 4;
  std::vector<std::uint8_t> samples(pixels * static_cast<std::size_t>(channels));
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* pixel = &rgba[4 * i];
    if (channels == 1) {
      samples[i] = static_cast<std::uint8_t>((pixel[0] + pixel[1] + pixel[2] + 1) / 3);
    } else {
      std::copy(pixel, pixel + 3, &samples[3 * i]);
    }
  }
  return samples;
}

// ---------------------------------------------------------------------------
// Drawing helpers; sizes and positions are in pixels of the picture.

// Literal text for PLplot: valid UTF-8 and its escape character doubled.
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
constexpr double kLeft = 70.0;
constexpr double kRight = 22.0;
constexpr double kBottom = 58.0;
constexpr double kTitleSize = 15.0;
constexpr double kLabelSize = 13.0;
constexpr double kTickSize = 12.0;

// The title centred over the plot area, which ends `right` pixels from the
// right edge.
void draw_title(const Canvas& canvas, const std::string& title, double right = kRight) {
  canvas.text((kLeft + canvas.width() - right) / 2.0, 22.0, 0.5, kTitleSize, kInk, title);
}

// Frame, ticks and tick labels of the current window, and the axis labels
// (PLplot text).
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

// The x axis of a spectrum: ticks and labels at multiples of pi / 2.
void draw_frequency_labels(const Canvas& canvas) {
  canvas.text_height(kTickSize);
  plcol0(kInk);
  const char* labels[] = {"−π", "−π/2", "0", "π/2", "π"};
  for (int i = 0; i < 5; ++i) plmtex("b", 1.6, i / 4.0, 0.5, labels[i]);
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

// A dot of `radius` pixels centred on the world point (x, y) of the current
// viewport and window, which are kept.
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

// Light vertical lines at multiples of pi / 2.
void draw_frequency_grid(double y_min, double y_max) {
  plcol0(kGrid);
  plwidth(0.5);
  pllsty(1);
  for (int i = -1; i <= 1; ++i) pljoin(i * M_PI / 2.0, y_min, i * M_PI / 2.0, y_max);
}

struct LegendEntry {
  std::string text;
  PLINT colour;
  PLINT line_style;  // 0: a dot instead of a line
  double line_width;
};

// At most `limit` characters of `text`, an ellipsis replacing the rest.
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

// Number of characters (code points) of UTF-8 text.
std::size_t characters(const std::string& text) {
  std::size_t count = 0;
  for (const char c : text) count += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return count;
}

// Legend entries from (x, y) pixels, in a row or one under the other: a
// 28-pixel sample of the line (or a dot), then the text.
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

}  // namespace

// ---------------------------------------------------------------------------

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
  const std::vector<double> code = abs_k(gains, velocity, dt, xi);
  const std::vector<double> snapshot = abs_k({1.0}, velocity, dt, xi);
  double top = 0.0;
  for (std::size_t j = 0; j < xi.size(); ++j) top = std::max({top, code[j], snapshot[j]});
  if (!(top > 0.0)) top = 1.0;
  top *= 1.06;
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
    plwind(-M_PI, M_PI, 0.0, top);
    draw_frequency_grid(0.0, top);
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
    draw_dot(canvas, kernel.min_abs_xi, kernel.min_abs, 4.5, kMarker);
    if (kernel.min_abs_xi > 0.0) draw_dot(canvas, -kernel.min_abs_xi, kernel.min_abs, 4.5, kMarker);
    draw_axes(canvas, "bcst", M_PI / 2.0, "bcnstv", "ξ (radians per pixel)", "|K(ξ)|");
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

// The y range of an overlay; on a log scale, the curves become log10 |K|,
// zeros (below 1e-4 of the top) drawn at the bottom edge.
std::pair<double, double> overlay_y_range(OverlayCurves& o, bool log_scale) {
  if (!log_scale) return {0.0, o.top * 1.06};
  double bottom = HUGE_VAL;
  for (const auto& curve : o.curves) {
    for (const double value : curve) {
      if (value > o.top * 1e-4) bottom = std::min(bottom, value);
    }
  }
  const double y_low = std::floor(std::log10(bottom));
  for (auto& curve : o.curves) {
    for (double& value : curve) value = std::log10(std::max(value, std::pow(10.0, y_low)));
  }
  return {y_low, std::log10(o.top) + 0.08};
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

namespace {

// Width of a figure sheet of `panels`; a usage error unless they can make one.
int sheet_width(const std::vector<SheetPanel>& panels) {
  if (panels.empty()) throw_usage_error("a figure sheet needs at least one image");
  const int height = panels[0].image != nullptr ? panels[0].image->height : 0;
  const int channels = panels[0].image != nullptr ? panels[0].image->channels : 0;
  int width = kSheetMargin;
  for (const SheetPanel& panel : panels) {
    const Image* image = panel.image;
    if (image == nullptr || image->width <= 0 || image->height != height ||
        image->channels != channels || (channels != 1 && channels != 3) ||
        image->data.size() != image->plane_size() * channels) {
      throw_usage_error(
          "the images of a figure sheet must be non-empty, of equal heights and of equal channel "
          "counts (1 or 3)");
    }
    width += image->width + kSheetMargin;
  }
  return width;
}

// Copies the panels into `rgba` (`width` pixels a row) below the header, a
// margin apart; returns the x of their centres.
std::vector<double> paste_panels(const std::vector<SheetPanel>& panels, int width,
                                 std::vector<std::uint8_t>& rgba) {
  std::vector<double> centres;
  int left = kSheetMargin;
  for (const SheetPanel& panel : panels) {
    const Image& image = *panel.image;
    for (int y = 0; y < image.height; ++y) {
      std::uint8_t* row =
          &rgba[(static_cast<std::size_t>(kSheetHeaderHeight + y) * width + left) * 4];
      for (int x = 0; x < image.width; ++x) {
        for (int c = 0; c < 3; ++c) {
          row[4 * x + c] = png8_sample(image.at(image.channels == 1 ? 0 : c, y, x));
        }
      }
    }
    centres.push_back(left + image.width / 2.0);
    left += image.width + kSheetMargin;
  }
  return centres;
}

}  // namespace

std::vector<std::uint8_t> figure_sheet_png(const std::vector<SheetPanel>& panels,
                                           const std::string& title) {
  const int width = sheet_width(panels);
  const int height = panels[0].image->height, channels = panels[0].image->channels;
  const int sheet_height = kSheetHeaderHeight + height + kSheetMargin;
  if (width > 32767 || sheet_height > 32767) {
    throw_usage_error("a figure sheet of " + std::to_string(width) + "x" +
                      std::to_string(sheet_height) + " pixels is too large (32767 at most)");
  }
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * sheet_height * 4, 255);
  const std::vector<double> centres = paste_panels(panels, width, rgba);
  render(width, sheet_height, rgba, [&] {
    const Canvas canvas(width, sheet_height);
    // About 7.5 pixels per character at this size: cut what would not fit.
    const auto fit = [](const std::string& text, double pixels) {
      return literal(ellipsize(text, static_cast<std::size_t>(std::max(4.0, pixels / 7.5))));
    };
    canvas.text(kSheetMargin, 14.0, 0.0, 13.0, kInk, fit(title, width - 2.0 * kSheetMargin));
    for (std::size_t i = 0; i < panels.size(); ++i) {
      canvas.text(centres[i], kSheetHeaderHeight - 12.0, 0.5, 13.0, kInk,
                  fit(panels[i].caption, panels[i].image->width));
    }
  });
  return encode_png8_samples(width, sheet_height, channels, to_samples(rgba, channels));
}

namespace {

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
