#include "sweep_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "cli_common.h"
#include "fss/model/code.h"
#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/simulate.h"
#include "range.h"

namespace fssim {

namespace {

const char kCsvHeader[] =
    "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,snr_level100,"
    "invertible,status\n";

// A CSV number: 10 significant digits for the swept values (so that 0.1 steps
// read 0.3, not 0.30000000000000004), full precision for the results; "inf"
// for an infinite one.
std::string csv_number(double value, int digits = 17) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

// SPEC 4 and 5: blur length B = max(L, ceil(|v| dt L)); the outputs are
// W - 3B wide; the RMSE window [margin, W - 3B - margin) and the RMSE_CI
// window [B, W - 4B) must not be empty. Returns "" when the setting fits,
// otherwise why it does not.
std::string too_narrow_reason(int width, int length, double velocity, double dt, int margin,
                              int* blur_length) {
  const double motion = std::ceil(std::abs(velocity) * dt * length);
  if (!(motion < width)) {
    *blur_length = -1;
    return "the blur spans " + format_number(motion) + " pixels, more than the image width " +
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

}  // namespace

SweepCommand::SweepCommand(CLI::App& app) {
  sweep_ = app.add_subcommand(
      "sweep",
      "simulate over a range of velocities and/or snr values and write one CSV row per setting "
      "(measured and predicted RMSE)");
  sweep_->add_option("-i,--input", input_, "input PNG image")->required();
  sweep_
      ->add_option(
          "-c,--code", code_name_,
          "shutter code: snapshot, accumulation, raskar, random, mip, sinc, or a code file")
      ->capture_default_str();
  sweep_
      ->add_option("-m,--mode", mode_,
                   "numerical (burst of frames, any real gains) or analog (gains in [0,1])")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  sweep_
      ->add_option("-v,--velocity", velocity_,
                   "velocity V, or a range start:stop:step (inclusive stop), pixels per slot")
      ->capture_default_str();
  sweep_->add_option("--snr", snr_, "snr S, or a range start:stop:step; values > 0")
      ->capture_default_str();
  sweep_->add_option("--dt", options_.dt, "time slot length, > 0")
      ->check(finite() & positive())
      ->capture_default_str();
  sweep_->add_option("--trials", options_.trials, "noise realizations per setting")
      ->check(at_least(1))
      ->capture_default_str();
  sweep_
      ->add_option("--seed", options_.seed,
                   "seed of the noise; every setting uses the same seeds (seed, seed+1, ...)")
      ->capture_default_str();
  sweep_
      ->add_option("--rmse-margin", options_.rmse_margin_columns,
                   "columns left out at each side of the output for the RMSE (default 3B)")
      ->check(at_least(0));
  sweep_->add_option("--threads", options_.threads, "worker threads, 0 = all cores")
      ->check(at_least(0))
      ->capture_default_str();
  sweep_->add_option("-o,--output", output_, "CSV file to write")->required();
  sweep_->add_option("--plot", plot_,
                     "also draw measured and predicted RMSE against the swept parameter into "
                     "this PNG (one of --velocity, --snr must be a range)");
}

bool SweepCommand::parsed() const { return sweep_->parsed(); }

int SweepCommand::Run() const {
  return run_reporting_errors([this] { return RunSweep(); });
}

int SweepCommand::RunSweep() const {
  const std::vector<double> velocities = parse_range(velocity_, "--velocity");
  const std::vector<double> snrs = parse_range(snr_, "--snr");
  for (const double snr : snrs) {
    if (!(snr > 0.0)) {
      fss::throw_usage_error("--snr '" + snr_ + "': every value must be > 0, got " +
                             format_number(snr));
    }
  }
  if (velocities.size() * snrs.size() > static_cast<std::size_t>(kMaxRangePoints)) {
    fss::throw_usage_error("--velocity '" + velocity_ + "' and --snr '" + snr_ + "' make " +
                           std::to_string(velocities.size() * snrs.size()) +
                           " settings, more than " + std::to_string(kMaxRangePoints));
  }
  const bool by_velocity = velocities.size() > 1;
  if (!plot_.empty() && velocities.size() > 1 && snrs.size() > 1) {
    fss::throw_usage_error(
        "--plot draws one curve: give a range to --velocity or to --snr, not "
        "to both");
  }
  std::error_code ec;
  if (!plot_.empty() && (std::filesystem::equivalent(input_, plot_, ec) || plot_ == output_)) {
    fss::throw_runtime_error("--plot '" + plot_ + "' must differ from the input and the CSV");
  }
  if (std::filesystem::equivalent(input_, output_, ec)) {
    fss::throw_runtime_error("refusing to write the CSV '" + output_ + "' over the input");
  }
  const fss::ShutterCode code = fss::load_code(code_name_);
  const fss::Image image = fss::read_png(input_);

  fss::SimulationOptions options = options_;
  options.mode = *fss::shutter_mode_from_string(mode_);
  // Refuse a code the mode cannot use before any row runs (Simulate would, at
  // the first setting that fits the image).
  fss::check_code_for_mode(code, options.mode);
  std::string csv = kCsvHeader;
  int rows = 0;
  // For --plot: the swept values, the measured mean and the prediction (NaN
  // where a setting has none).
  std::vector<double> plot_x, plot_measured, plot_predicted;
  for (const double velocity : velocities) {
    for (const double snr : snrs) {
      options.velocity_px_per_slot = velocity;
      options.snr = snr;
      const std::string setting = csv_number(velocity, 10) + "," + csv_number(snr, 10) + ",";
      int blur_length = 0;
      const std::string reason = too_narrow_reason(image.width, code.length(), velocity, options.dt,
                                                   options.rmse_margin_columns, &blur_length);
      ++rows;
      if (!reason.empty()) {
        std::cerr << "fssim: warning: velocity " << format_number(velocity) << ": " << reason
                  << "; row marked too-narrow (see --rmse-margin)\n";
        csv +=
            setting + (blur_length > 0 ? std::to_string(blur_length) : "") + ",,,,,,,too-narrow\n";
        plot_x.push_back(by_velocity ? velocity : snr);
        plot_measured.push_back(std::nan(""));
        plot_predicted.push_back(std::nan(""));
        std::printf("velocity %g, snr %g: too narrow\n", velocity, snr);
        continue;
      }
      const fss::SimulationReport r = fss::Simulate(options, image, code);
      const fss::Prediction& p = r.prediction;
      plot_x.push_back(by_velocity ? velocity : snr);
      plot_measured.push_back(r.trials.rmse_mean);
      plot_predicted.push_back(p.finite ? p.rmse : std::nan(""));
      csv += setting + std::to_string(r.geometry.blur_length) + "," +
             csv_number(r.trials.rmse_mean) + "," + csv_number(r.trials.rmse_sd) + "," +
             csv_number(p.rmse) + "," + csv_number(p.rmse_noise_free) + "," +
             csv_number(p.snr_level100) + "," + (r.kernel.invertible ? "true" : "false") + "," +
             (r.kernel.invertible ? "ok" : "not-invertible") + "\n";
      if (p.finite) {
        std::printf("velocity %g, snr %g: RMSE %f (sd %f, %d trials), predicted %f\n", velocity,
                    snr, r.trials.rmse_mean, r.trials.rmse_sd, r.trials.n, p.rmse);
      } else {
        std::printf("velocity %g, snr %g: RMSE %g (%d trials), not invertible\n", velocity, snr,
                    r.trials.rmse_mean, r.trials.n);
      }
    }
  }
  std::vector<std::uint8_t> png;
  if (!plot_.empty()) {
    const std::string trials =
        std::to_string(options.trials) + (options.trials == 1 ? " realization" : " realizations");
    fss::PlotOptions plot_options;
    plot_options.title = "RMSE of code " + code.name + " on " +
                         std::filesystem::path(input_).filename().string() + ", " +
                         fss::to_string(options.mode) +
                         (by_velocity ? ", snr " + format_number(snrs.front())
                                      : ", velocity " + format_number(velocities.front()));
    png =
        fss::plot_curves_png(plot_x,
                             {{"measured (mean of " + trials + ")", plot_measured, false, true},
                              {"predicted, sqrt(RMSE_0^2 + sigma^2)", plot_predicted, true, false}},
                             by_velocity ? "velocity (pixels per time slot)" : "snr",
                             "RMSE (gray levels)", plot_options);
  }
  write_file_atomically(output_, csv);
  std::printf("Wrote %d rows to %s\n", rows, output_.c_str());
  if (!plot_.empty()) {
    write_file_atomically(plot_, std::string(png.begin(), png.end()));
    std::printf("Plot: %s\n", plot_.c_str());
  }
  return 0;
}

}  // namespace fssim
