#include "io/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/text_util.h"
#include "fss/io/plot.h"
#include "io/run_files.h"

namespace fss {

namespace {

std::string format(const char* pattern, double value) {
  if (std::isnan(value)) return "—";
  if (std::isinf(value)) return value > 0 ? "∞" : "−∞";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// A measured or predicted error: fixed point as on stdout, unless huge.
std::string metric(double value) { return format(std::abs(value) < 1e6 ? "%.6f" : "%.6g", value); }

std::string colour(const RunFile& f) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", f.frame.red, f.frame.green, f.frame.blue);
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

void write_figure(std::ostringstream& out, const RunFile& f, int width, int height) {
  out << "<figure><img src=\"" << f.name << "\" width=\"" << width << "\" height=\"" << height
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

// What a file of the run holds, as the list of files says; empty if it is
// not a file of run_files().
std::string content_of(const std::string& name) {
  for (const RunFile& file : run_files()) {
    if (name == file.name) return file.content;
  }
  return "";
}

void write_head(std::ostringstream& out, const std::string& code, const std::string& input_path) {
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
}

// The heading, the run in one sentence and its warnings.
void write_summary(std::ostringstream& out, const SimulationReport& r, const std::string& code,
                   const std::string& input_path) {
  const SimulationOptions& o = r.options;
  out << "<h1>Flutter shutter simulation: code <code>" << code << "</code></h1>\n"
      << "<p>Input <code>" << html_escape(input_path) << "</code>, " << r.width << "×" << r.height
      << ", " << (r.channels == 1 ? "gray" : "colour") << ". "
      << (o.mode == ShutterMode::kAnalog ? "Analog" : "Numerical") << " flutter shutter, v "
      << (o.velocity_distribution
              ? "drawn by each trial from the " + html_escape(o.velocity_distribution->describe()) +
                    " (pixels per time slot)"
              : "= " + format("%g", o.velocity_px_per_slot) + " pixel per time slot")
      << ", dt = " << format("%g", o.dt) << ", snr = " << format("%g", o.snr) << ".</p>\n";
  if (r.warnings.empty()) return;
  out << "<ul class=\"warning\">\n";
  for (const std::string& warning : r.warnings) {
    out << "<li>warning: " << html_escape(warning) << "</li>\n";
  }
  out << "</ul>\n";
}

void write_parameters(std::ostringstream& out, const SimulationReport& r, const std::string& code) {
  const SimulationOptions& o = r.options;
  const int first_column = 3 * r.geometry.half_blur;
  Table t(out);
  t.row("code", "<code>" + code + "</code>, L = " + std::to_string(r.gains.size()) +
                    ", ‖α‖₁ / sup|α| = " + format("%.4f", normalized_l1(r.gains)));
  t.row("mode", to_string(o.mode));
  if (o.velocity_distribution) {  // docs/method.md §13
    t.row("velocity distribution",
          html_escape(o.velocity_distribution->describe()) + " (<code>" +
              html_escape(o.velocity_distribution->text()) +
              "</code>); the first trial's v = " + format("%g", first_trial_velocity(o)));
  } else {
    t.row("velocity v", format("%g", o.velocity_px_per_slot) + " (pixels per time slot)");
  }
  t.row("slot length dt", format("%g", o.dt));
  t.row("snr", format("%g", o.snr));
  t.row("noise", to_string(o.noise));
  t.row("seed", std::to_string(o.seed));
  t.row("trials", std::to_string(o.trials));
  if (o.sensor.enabled()) {  // docs/method.md §10
    const SensorModel& s = o.sensor;
    t.row("sensor",
          "read noise " + format("%g", s.read_noise_electrons) + " e⁻, dark current " +
              format("%g", s.dark_current_electrons_per_slot) + " e⁻/slot, full well " +
              (s.full_well_electrons ? format("%g", *s.full_well_electrons) + " e⁻" : "none") +
              ", ADC " +
              (s.adc_bits != 0 ? std::to_string(s.adc_bits) + " bits, " +
                                     format("%g", s.adc_gain_electrons_per_count) + " e⁻/count"
                               : "none"));
  }
  t.row("blur length B", std::to_string(r.geometry.blur_length) + " pixels");
  t.row("output crop", std::to_string(r.geometry.output_width) + "×" + std::to_string(r.height) +
                           ", input columns " + std::to_string(first_column) + " … " +
                           std::to_string(first_column + r.geometry.output_width - 1));
  t.row("RMSE columns", columns(r.rmse_first, r.rmse_end) + " of the output");
  t.row("RMSE_CI columns", columns(r.rmse_ci_first, r.rmse_ci_end));
}

// Under a velocity distribution (docs/method.md §13): the trials' mean MSE against E[MSE].
void write_mse_rows(Table& t, const SimulationReport& r) {
  if (!r.trials.mse_mean) return;
  const Prediction& p = r.prediction;
  t.row("MSE over " + std::to_string(r.trials.n) + " trials",
        metric(*r.trials.mse_mean) + " ± " + metric(r.trials.mse_sd.value_or(0.0)) +
            " (mean ± sd; se " +
            metric(r.trials.mse_sd.value_or(0.0) / std::sqrt(static_cast<double>(r.trials.n))) +
            ")");
  t.row(
      "predicted expected MSE",
      p.finite && p.mse
          ? metric(*p.mse) + " (√: " + metric(p.rmse) + "; " + std::to_string(p.mse_evaluations) +
                " velocities evaluated)"
          : "<span class=\"warning\">infinite: " + html_escape(p.mse_infinite_reason) + "</span>");
}

// The predicted error: the exact expectation (docs/method.md §6b), the
// stationary approximation and the figure of merit (§6), and |K| (§1).
void write_prediction_rows(Table& t, const SimulationReport& r) {
  write_mse_rows(t, r);
  if (r.prediction.finite && !r.options.velocity_distribution) {
    t.row(r.prediction.exact ? "predicted RMSE (exact expectation)"
                             : "predicted RMSE (approximate: the sensor clips readouts)",
          metric(r.prediction.rmse));
    t.row("noise-free RMSE", metric(r.prediction.rmse_noise_free));
    t.row("noise part (exact)", metric(r.prediction.noise));
    t.row("stationary approximation: RMSE", metric(r.prediction.rmse_stationary));
    t.row("stationary approximation: noise σ", metric(r.prediction.sigma));
    if (r.options.restoration.method == RestorationMethod::kInverse) {
      t.row("SNR at level 100 (stationary figure of merit)",
            format("%.3f", r.prediction.snr_level100));
    }
  } else if (!r.options.velocity_distribution) {
    t.row("predicted RMSE", "<span class=\"warning\">none: the code is not invertible</span>");
    t.row("noise-free RMSE", metric(r.prediction.rmse_noise_free));
  }
  t.row("K(0)", format("%.6g", r.kernel.k0));
  t.row(r.options.velocity_distribution ? "min |K| (the first trial's)" : "min |K|",
        format("%.6g", r.kernel.min_abs) + " at ξ = " + (r.kernel.min_abs_xi > 0.0 ? "±" : "") +
            format("%.6g", r.kernel.min_abs_xi) +
            (r.kernel.invertible ? "" : " <span class=\"warning\">(zero)</span>"));
}

// The measured errors (docs/method.md §5), then the predicted ones.
void write_metrics(std::ostringstream& out, const SimulationReport& r) {
  Table t(out);
  t.row("RMSE (measured)", metric(r.metrics.rmse));
  t.row("PSNR", metric(r.metrics.psnr) + " dB");
  t.row("RMSE_CI (contrast invariant)", metric(r.metrics.rmse_ci));
  t.row("PSNR_CI", metric(r.metrics.psnr_ci) + " dB");
  t.row("SSIM", r.metrics.ssim ? metric(*r.metrics.ssim) : "none (no pixel left)");
  if (r.options.restoration.method != RestorationMethod::kInverse) {
    t.row("restoration", html_escape(describe(r.restoration.options)));
  }
  if (r.trials.n > 1) {
    t.row("RMSE over " + std::to_string(r.trials.n) + " trials",
          metric(r.trials.rmse_mean) + " ± " + metric(r.trials.rmse_sd) + " (mean ± sd)");
    t.row("RMSE_CI over " + std::to_string(r.trials.n) + " trials",
          metric(r.trials.rmse_ci_mean) + " ± " + metric(r.trials.rmse_ci_sd));
  }
  if (r.trials.n > 1 && r.trials.ssim_mean) {
    t.row("SSIM over " + std::to_string(r.trials.n) + " trials",
          metric(*r.trials.ssim_mean) + " ± " + metric(r.trials.ssim_sd.value_or(0.0)));
  }
  write_prediction_rows(t, r);
}

// One row of figures: those of `kind` among `output_files`, under `heading`;
// nothing when there are none.
void write_figure_row(std::ostringstream& out, const std::vector<std::string>& output_files,
                      RunFileFigure kind, const char* heading, const char* id, int width,
                      int height) {
  std::vector<RunFile> shown;
  for (const RunFile& file : run_files()) {
    if (file.figure == kind && contains(output_files, file.name)) shown.push_back(file);
  }
  if (shown.empty()) return;
  out << "<h2>" << heading << "</h2>\n<div class=\"row\" id=\"" << id << "\">\n";
  for (const RunFile& file : shown) write_figure(out, file, width, height);
  out << "</div>\n";
}

void write_file_list(std::ostringstream& out, const std::vector<std::string>& output_files) {
  out << "<h2>Files</h2>\n<ul>\n";
  for (const std::string& file : output_files) {
    const std::string name = html_escape(file);
    const std::string text = content_of(file);
    out << "<li><a href=\"" << name << "\">" << name << "</a>"
        << (text.empty() ? "" : ": " + html_escape(text)) << "</li>\n";
  }
  out << "</ul>\n";
}

}  // namespace

const std::vector<ReportFigure>& report_figures() {
  static const std::vector<ReportFigure> figures = [] {
    std::vector<ReportFigure> found;
    for (const RunFile& file : run_files()) {
      if (file.figure != RunFileFigure::kNone) {
        found.push_back(
            {file.name, file.caption, file.frame.red, file.frame.green, file.frame.blue});
      }
    }
    return found;
  }();
  return figures;
}

std::string html_escape(std::string_view text) {
  return detail::escape_markup(detail::sanitize_utf8(text), true);
}

std::string html_report(const SimulationReport& r, const std::string& input_path,
                        const std::vector<std::string>& output_files) {
  const std::string code = html_escape(r.code_name);
  std::ostringstream out;
  write_head(out, code, input_path);
  write_summary(out, r, code, input_path);
  out << "<div class=\"tables\">\n<section>\n<h2>Parameters</h2>\n";
  write_parameters(out, r, code);
  out << "</section>\n<section>\n<h2>Metrics</h2>\n";
  write_metrics(out, r);
  out << "</section>\n</div>\n";
  write_figure_row(out, output_files, RunFileFigure::kImage, "Images", "images",
                   r.geometry.output_width, r.height);
  write_figure_row(out, output_files, RunFileFigure::kPlot, "Code and spectrum", "plots",
                   kPlotWidth, kPlotHeight);
  write_file_list(out, output_files);
  out << "<p>Made by fssim " << FSS_VERSION
      << ", a re-implementation of <i>The Flutter Shutter Camera Simulator</i> (Y. Tendero, IPOL "
         "2012).</p>\n</body>\n</html>\n";
  return out.str();
}

}  // namespace fss
