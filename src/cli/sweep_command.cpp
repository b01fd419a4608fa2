#include "sweep_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <utility>

#include "cli_common.h"
#include "fss/core/error.h"
#include "fss/io/image_io.h"
#include "fss/io/plot.h"
#include "fss/io/safe_write.h"
#include "fss/model/code.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/simulate.h"
#include "range.h"

namespace fssim {

namespace {

const char kCsvHeader[] =
    "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,snr_level100,"
    "invertible,status\n";

// CSV numbers: 10 significant digits for the swept values (so that 0.1 steps
// read 0.3, not 0.30000000000000004), full precision for the results.
constexpr int kSettingDigits = 10;
constexpr int kResultDigits = 17;

std::string csv_number(double value, int digits = kResultDigits) {
  return format_number(value, digits);
}

// docs/method.md §4 and §5: blur length B = max(L, ceil(|v| dt L)); the
// outputs are W - 3B wide; the RMSE window [margin, W - 3B - margin) and the
// RMSE_CI window [B, W - 4B) must not be empty. Returns "" when the setting
// fits, otherwise why it does not.
std::string too_narrow_reason(int width, int length, double velocity, double dt, int margin,
                              int* blur_length) {
  const double motion = std::ceil(std::abs(velocity) * dt * length);
  if (!(motion < width)) {
    *blur_length = -1;
    return "the blur spans " + format_exact(motion) + " pixels, more than the image width " +
           std::to_string(width);
  }
  const int b = std::max(length, static_cast<int>(motion));
  *blur_length = b;
  const int m = margin < 0 ? 3 * b : margin;
  const int output = width - 3 * b;
  if (output <= 2 * b || output <= 2 * m) {
    const int needed = std::max(5 * b, 3 * b + 2 * m) + 1;
    return "image width " + std::to_string(width) +
           " is too narrow for blur length B = " + std::to_string(b) + " and RMSE margin " +
           std::to_string(m) + " (needs " + std::to_string(needed) + ")";
  }
  return {};
}

// The swept values and the results, for --plot (NaN where a setting has none).
struct Curves {
  std::vector<double> x, measured, predicted;
};

// One setting: its CSV row and its console line; the curves get its point.
class SweepRunner {
 public:
  SweepRunner(const fss::SimulationOptions& options, const fss::Image& image,
              const fss::ShutterCode& code, bool by_velocity, std::FILE* console)
      : options_(options),
        image_(image),
        code_(code),
        by_velocity_(by_velocity),
        console_(console) {}

  std::string Row(double velocity, double snr);
  const Curves& curves() const { return curves_; }

 private:
  std::string TooNarrowRow(double velocity, double snr, const std::string& reason, int blur_length);

  fss::SimulationOptions options_;
  const fss::Image& image_;
  const fss::ShutterCode& code_;
  bool by_velocity_;
  std::FILE* console_;  // stdout, or stderr when the CSV goes to stdout
  Curves curves_;
};

std::string SweepRunner::TooNarrowRow(double velocity, double snr, const std::string& reason,
                                      int blur_length) {
  fss::write_stderr("fssim: warning: velocity " + format_exact(velocity) + ": " + reason +
                    "; row marked too-narrow (see --rmse-margin)\n");
  curves_.x.push_back(by_velocity_ ? velocity : snr);
  curves_.measured.push_back(std::nan(""));
  curves_.predicted.push_back(std::nan(""));
  std::fprintf(console_, "velocity %g, snr %g: too narrow\n", velocity, snr);
  return (blur_length > 0 ? std::to_string(blur_length) : "") + ",,,,,,,too-narrow\n";
}

std::string SweepRunner::Row(double velocity, double snr) {
  options_.velocity_px_per_slot = velocity;
  options_.snr = snr;
  const std::string setting =
      csv_number(velocity, kSettingDigits) + "," + csv_number(snr, kSettingDigits) + ",";
  int blur_length = 0;
  const std::string reason = too_narrow_reason(image_.width, code_.length(), velocity, options_.dt,
                                               options_.rmse_margin_columns, &blur_length);
  if (!reason.empty()) return setting + TooNarrowRow(velocity, snr, reason, blur_length);
  const fss::SimulationReport r = fss::Simulate(options_, image_, code_);
  const fss::Prediction& p = r.prediction;
  curves_.x.push_back(by_velocity_ ? velocity : snr);
  curves_.measured.push_back(r.trials.rmse_mean);
  curves_.predicted.push_back(p.finite ? p.rmse : std::nan(""));
  if (p.finite) {
    std::fprintf(console_, "velocity %g, snr %g: RMSE %f (sd %f, %d trial%s), predicted %f\n",
                 velocity, snr, r.trials.rmse_mean, r.trials.rmse_sd, r.trials.n,
                 r.trials.n == 1 ? "" : "s", p.rmse);
  } else {
    std::fprintf(console_, "velocity %g, snr %g: RMSE %g (%d trial%s), not invertible\n", velocity,
                 snr, r.trials.rmse_mean, r.trials.n, r.trials.n == 1 ? "" : "s");
  }
  return setting + std::to_string(r.geometry.blur_length) + "," + csv_number(r.trials.rmse_mean) +
         "," + csv_number(r.trials.rmse_sd) + "," + csv_number(p.rmse) + "," +
         csv_number(p.rmse_noise_free) + "," + csv_number(p.snr_level100) + "," +
         (r.kernel.invertible ? "true" : "false") + "," +
         (r.kernel.invertible ? "ok" : "not-invertible") + "\n";
}

// Every value of --snr 'TEXT' as the simulator's rule has it (> 0, within
// the library's range). The message shows TEXT as typed, and for a range
// the value that breaks the rule.
void check_snr_values(const std::vector<double>& snrs, const std::string& text) {
  for (const double snr : snrs) {
    const std::string rule = snr > 0.0 ? fss::scale_rule(snr) : "must be > 0";
    if (rule.empty()) continue;
    std::string message = "--snr '" + text + "': ";
    message += snrs.size() == 1 ? "the value " + rule
                                : "every value " + rule + ", the range holds " + format_exact(snr);
    fss::throw_usage_error(message);
  }
}

}  // namespace

SweepCommand::SweepCommand(CLI::App& app) {
  sweep_ = app.add_subcommand(
      "sweep",
      "simulate over a range of velocities and/or snr values and write one CSV row per setting "
      "(measured and predicted RMSE)");
  sweep_->add_option("-i,--input", input_, "input PNG or TIFF image")->required();
  flags_.AddCode(*sweep_);
  flags_.AddMode(*sweep_);
  sweep_
      ->add_option("-v,--velocity", velocity_,
                   "velocity V, or a range start:stop:step (inclusive stop), pixels per slot")
      ->capture_default_str();
  sweep_->add_option("--snr", snr_, "snr S, or a range start:stop:step; values > 0")
      ->capture_default_str();
  flags_.AddDt(*sweep_);
  flags_.AddTrials(*sweep_);
  flags_.AddSeed(*sweep_);
  flags_.AddNoise(*sweep_);
  flags_.AddRmseMargin(*sweep_);
  flags_.AddThreads(*sweep_);
  flags_.AddMaxMemory(*sweep_);  // the simulator's memory guard, for the image and each row
  sweep_->add_option("-o,--output", output_, "CSV file to write (-: standard output)")->required();
  sweep_->add_option("--plot", plot_,
                     "also draw measured and predicted RMSE against the swept parameter into "
                     "this PNG (one of --velocity, --snr must be a range)");
}

bool SweepCommand::parsed() const { return sweep_->parsed(); }

int SweepCommand::Run() const {
  const ErrorContext context{" (raise it with --max-memory)", ""};
  return run_reporting_errors([this] { return Sweep(); }, &context);
}

SweepCommand::Grid SweepCommand::ParseGrid() const {
  Grid grid{parse_range(velocity_, "--velocity"), parse_range(snr_, "--snr")};
  check_snr_values(grid.snrs, snr_);
  const std::size_t settings = grid.velocities.size() * grid.snrs.size();
  if (settings > static_cast<std::size_t>(kMaxRangePoints)) {
    fss::throw_usage_error("--velocity '" + velocity_ + "' and --snr '" + snr_ + "' make " +
                           std::to_string(settings) + " settings, more than " +
                           std::to_string(kMaxRangePoints));
  }
  if (!plot_.empty() && grid.velocities.size() > 1 && grid.snrs.size() > 1) {
    fss::throw_usage_error(
        "--plot draws one curve: give a range to --velocity or to --snr, not "
        "to both");
  }
  return grid;
}

// The inputs (image, code file) are never written over (write_output
// checks them again), and --output and --plot must be two files.
void SweepCommand::CheckPaths() const {
  const std::vector<std::string> inputs = {input_, flags_.code_name()};
  for (const auto& [option, path] : {std::pair{"--output", &output_}, {"--plot", &plot_}}) {
    for (const std::string& input : inputs) {
      if (!path->empty() && !is_stdout(*path) && fss::same_file(*path, input)) {
        fss::throw_runtime_error(std::string(option) + " '" + *path + "' is the input '" + input +
                                 "': refusing to write over it");
      }
    }
  }
  if (!plot_.empty() && (is_stdout(plot_) ? is_stdout(output_) : fss::same_file(plot_, output_))) {
    fss::throw_usage_error("--plot '" + plot_ + "' and --output '" + output_ +
                           "' are the same file: give two");
  }
}

int SweepCommand::Sweep() const {
  const Grid grid = ParseGrid();
  CheckPaths();
  const fss::ShutterCode code = fss::load_code(flags_.code_name(), "--code");
  const fss::SimulationOptions options = flags_.Options();
  const fss::Image image = fss::read_image(input_, options.max_memory_bytes);
  // Refuse a code the mode cannot use before any row runs (Simulate would, at
  // the first setting that fits the image).
  fss::check_code_for_mode(code, options.mode);
  const bool on_stdout = is_stdout(output_) || is_stdout(plot_);
  SweepRunner runner(options, image, code, grid.by_velocity(), on_stdout ? stderr : stdout);
  std::string csv = kCsvHeader;
  int rows = 0;
  for (const double velocity : grid.velocities) {
    for (const double snr : grid.snrs) {
      csv += runner.Row(velocity, snr);
      ++rows;
    }
  }
  std::vector<std::uint8_t> png;
  if (!plot_.empty()) {
    const std::string trials =
        std::to_string(options.trials) + (options.trials == 1 ? " realization" : " realizations");
    fss::PlotOptions plot_options;
    plot_options.title =
        "RMSE of code " + code.name + " on " + std::filesystem::path(input_).filename().string() +
        ", " + fss::to_string(options.mode) +
        (grid.by_velocity() ? ", snr " + format_number(grid.snrs.front())
                            : ", velocity " + format_number(grid.velocities.front()));
    const Curves& c = runner.curves();
    png = fss::plot_curves_png(c.x,
                               {{"measured (mean of " + trials + ")", c.measured, false, true},
                                {"predicted (exact expectation)", c.predicted, true, false}},
                               grid.by_velocity() ? "velocity (pixels per time slot)" : "snr",
                               "RMSE (gray levels)", plot_options);
  }
  const std::vector<std::string> inputs = {input_, flags_.code_name()};
  std::FILE* console = on_stdout ? stderr : stdout;
  write_output(output_, csv, inputs);
  std::fprintf(console, "Wrote %d row%s to %s\n", rows, rows == 1 ? "" : "s", output_.c_str());
  if (!plot_.empty()) {
    write_output(plot_, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()),
                 inputs);
    std::fprintf(console, "Plot: %s\n", plot_.c_str());
  }
  return kExitSuccess;
}

}  // namespace fssim
