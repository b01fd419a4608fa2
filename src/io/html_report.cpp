#include "fss/io/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "fss/io/plot.h"
#include "core/text_util.h"

namespace fss {

namespace {

// Every frame colour has a zero component, which neither a gray image nor
// the plots' palette (all components >= 20) can produce.
const std::vector<ReportFigure> kFigures = {
    {"observed.png", "observed (divided by K(0))", 0, 114, 178},
    {"restored.png", "restored (inverse filter)", 0, 158, 115},
    {"groundtruth.png", "ground truth (input, same crop)", 230, 159, 0},
    {"residual.png", "residual (ground truth − restored, stretched to [0, 255])", 204, 0, 122},
    {"code.png", "gain function α(t)", 120, 0, 200},
    {"spectrum.png", "|K(ξ)|, the snapshot's dashed", 160, 130, 0},
};

constexpr int kImageCount = 4;

const char* describe(const std::string& file) {
  static const std::pair<const char*, const char*> kDescriptions[] = {
      {"observed.png", "the observation divided by K(0), output crop"},
      {"restored.png", "the inverse-filtered restoration, output crop"},
      {"groundtruth.png", "the input, same crop"},
      {"residual.png", "ground truth − restored, stretched to [0, 255]"},
      {"code.txt", "the gains, reference format"},
      {"spectrum.txt", "|K(ξ)| at 100 frequencies, reference format"},
      {"report.json", "every parameter and result"},
      {"code.png", "plot of the gain function"},
      {"spectrum.png", "plot of |K(ξ)| against the snapshot's"},
      {"sheet.png", "observed | restored | residual in one picture"},
      {"report.html", "this page"},
  };
  for (const auto& [name, text] : kDescriptions) {
    if (file == name) return text;
  }
  return "";
}

std::string format(const char* pattern, double value) {
  if (std::isnan(value)) return "—";
  if (std::isinf(value)) return value > 0 ? "∞" : "−∞";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// A measured or predicted error: fixed point as on stdout, unless huge.
std::string metric(double value) { return format(std::abs(value) < 1e6 ? "%.6f" : "%.6g", value); }

std::string colour(const ReportFigure& f) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", f.red, f.green, f.blue);
  return buffer;
}

// "[first, end)"
std::string columns(int first, int end) {
  std::ostringstream text;
  text << '[' << first << ", " << end << ')';
  return text.str();
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

class Table {
 public:
  explicit Table(std::ostringstream& out) : out_(out) { out_ << "<table>\n"; }
  ~Table() { out_ << "</table>\n"; }
  // `label` and `value` are HTML already.
  void row(const std::string& label, const std::string& value) {
    out_ << "<tr><th scope=\"row\">" << label << "</th><td>" << value << "</td></tr>\n";
  }

 private:
  std::ostringstream& out_;
};

void write_figure(std::ostringstream& out, const ReportFigure& f, int width, int height) {
  out << "<figure><img src=\"" << f.file << "\" width=\"" << width << "\" height=\"" << height
      << "\" alt=\"" << html_escape(f.caption) << "\" style=\"border-color: " << colour(f)
      << "\"><figcaption>" << html_escape(f.caption) << "</figcaption></figure>\n";
}

constexpr char kStyle[] =
    R"(body { font-family: "DejaVu Sans", sans-serif; font-size: 14px; color: #222; background: #fff; margin: 16px; }
h1 { font-size: 20px; margin: 0 0 8px 0; }
h2 { font-size: 16px; margin: 20px 0 8px 0; }
p { margin: 4px 0; }
.tables { display: flex; flex-wrap: wrap; gap: 12px 40px; align-items: flex-start; }
table { border-collapse: collapse; }
th, td { text-align: left; padding: 2px 12px 2px 0; border-bottom: 1px solid #e4e4e4; vertical-align: top; }
th { font-weight: normal; color: #555; }
td { font-variant-numeric: tabular-nums; }
.row { display: flex; flex-wrap: nowrap; gap: 12px; align-items: flex-start; }
figure { margin: 0; flex: 0 1 auto; min-width: 0; }
figcaption { font-size: 13px; margin-top: 4px; max-width: 40em; }
.warning { color: #b00000; }
code { font-family: "DejaVu Sans Mono", monospace; }
)";

}  // namespace

const std::vector<ReportFigure>& report_figures() { return kFigures; }

std::string html_escape(std::string_view text) {
  std::string out;
  for (const char c : detail::sanitize_utf8(text)) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string html_report(const SimulationReport& r, const std::string& input_path,
                        const std::vector<std::string>& output_files) {
  const std::string code = html_escape(r.code_name);
  const std::string input = html_escape(input_path);
  const SimulationOptions& o = r.options;
  const int first_column = 3 * r.geometry.half_blur;
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<title>fssim: " << code << " on " << html_escape(detail::base_name(input_path))
      << "</title>\n<style>\n"
      << kStyle
      // The width and height attributes are the picture's own size; the
      // frame goes around it, and a narrow window scales all pictures alike.
      << "figure img { display: block; box-sizing: content-box; height: auto; max-width: calc(100% "
         "- "
      << 2 * kReportFrameWidth << "px); border: " << kReportFrameWidth
      << "px solid; }\n</style>\n</head>\n<body>\n";
  out << "<h1>Flutter shutter simulation: code <code>" << code << "</code></h1>\n"
      << "<p>Input <code>" << input << "</code>, " << r.width << "×" << r.height << ", "
      << (r.channels == 1 ? "gray" : "colour") << ". "
      << (o.mode == ShutterMode::kAnalog ? "Analog" : "Numerical")
      << " flutter shutter, v = " << format("%g", o.velocity_px_per_slot)
      << " pixel per time slot, dt = " << format("%g", o.dt) << ", snr = " << format("%g", o.snr)
      << ".</p>\n";
  if (!r.warnings.empty()) {
    out << "<ul class=\"warning\">\n";
    for (const std::string& warning : r.warnings) {
      out << "<li>warning: " << html_escape(warning) << "</li>\n";
    }
    out << "</ul>\n";
  }

  out << "<div class=\"tables\">\n<section>\n<h2>Parameters</h2>\n";
  {
    Table t(out);
    t.row("code", "<code>" + code + "</code>, L = " + std::to_string(r.gains.size()) +
                      ", ‖α‖₁ / sup|α| = " + format("%.4f", normalized_l1(r.gains)));
    t.row("mode", to_string(o.mode));
    t.row("velocity v", format("%g", o.velocity_px_per_slot) + " (pixels per time slot)");
    t.row("slot length dt", format("%g", o.dt));
    t.row("snr", format("%g", o.snr));
    t.row("noise", to_string(o.noise));
    t.row("seed", std::to_string(o.seed));
    t.row("trials", std::to_string(o.trials));
    t.row("blur length B", std::to_string(r.geometry.blur_length) + " pixels");
    t.row("output crop", std::to_string(r.geometry.output_width) + "×" + std::to_string(r.height) +
                             ", input columns " + std::to_string(first_column) + " … " +
                             std::to_string(first_column + r.geometry.output_width - 1));
    t.row("RMSE columns", columns(r.rmse_first, r.rmse_end) + " of the output");
    t.row("RMSE_CI columns", columns(r.rmse_ci_first, r.rmse_ci_end));
  }
  out << "</section>\n<section>\n<h2>Metrics</h2>\n";
  {
    Table t(out);
    t.row("RMSE (measured)", metric(r.metrics.rmse));
    t.row("PSNR", metric(r.metrics.psnr) + " dB");
    t.row("RMSE_CI (contrast invariant)", metric(r.metrics.rmse_ci));
    t.row("PSNR_CI", metric(r.metrics.psnr_ci) + " dB");
    if (r.trials.n > 1) {
      t.row("RMSE over " + std::to_string(r.trials.n) + " trials",
            metric(r.trials.rmse_mean) + " ± " + metric(r.trials.rmse_sd) + " (mean ± sd)");
      t.row("RMSE_CI over " + std::to_string(r.trials.n) + " trials",
            metric(r.trials.rmse_ci_mean) + " ± " + metric(r.trials.rmse_ci_sd));
    }
    if (r.prediction.finite) {
      t.row("predicted RMSE", metric(r.prediction.rmse));
      t.row("noise-free RMSE", metric(r.prediction.rmse_noise_free));
      t.row("noise part σ", metric(r.prediction.sigma));
      t.row("SNR at level 100", format("%.3f", r.prediction.snr_level100));
    } else {
      t.row("predicted RMSE", "<span class=\"warning\">none: the code is not invertible</span>");
      t.row("noise-free RMSE", metric(r.prediction.rmse_noise_free));
    }
    t.row("K(0)", format("%.6g", r.kernel.k0));
    t.row("min |K|", format("%.6g", r.kernel.min_abs) +
                         " at ξ = " + (r.kernel.min_abs_xi > 0.0 ? "±" : "") +
                         format("%.6g", r.kernel.min_abs_xi) +
                         (r.kernel.invertible ? "" : " <span class=\"warning\">(zero)</span>"));
  }
  out << "</section>\n</div>\n";

  const int width = r.geometry.output_width, height = r.height;
  bool any_image = false, any_plot = false;
  for (int i = 0; i < static_cast<int>(kFigures.size()); ++i) {
    if (!contains(output_files, kFigures[i].file)) continue;
    if (i < kImageCount) {
      any_image = true;
    } else {
      any_plot = true;
    }
  }
  if (any_image) {
    out << "<h2>Images</h2>\n<div class=\"row\" id=\"images\">\n";
    for (int i = 0; i < kImageCount; ++i) {
      if (contains(output_files, kFigures[i].file)) write_figure(out, kFigures[i], width, height);
    }
    out << "</div>\n";
  }
  if (any_plot) {
    out << "<h2>Code and spectrum</h2>\n<div class=\"row\" id=\"plots\">\n";
    for (int i = kImageCount; i < static_cast<int>(kFigures.size()); ++i) {
      if (contains(output_files, kFigures[i].file)) {
        write_figure(out, kFigures[i], kPlotWidth, kPlotHeight);
      }
    }
    out << "</div>\n";
  }

  out << "<h2>Files</h2>\n<ul>\n";
  for (const std::string& file : output_files) {
    const std::string name = html_escape(file);
    const std::string text = describe(file);
    out << "<li><a href=\"" << name << "\">" << name << "</a>"
        << (text.empty() ? "" : ": " + html_escape(text)) << "</li>\n";
  }
  out << "</ul>\n<p>Made by fssim " << FSS_VERSION
      << ", a re-implementation of <i>The Flutter Shutter Camera Simulator</i> (Y. Tendero, IPOL "
         "2012).</p>\n</body>\n</html>\n";
  return out.str();
}

}  // namespace fss
