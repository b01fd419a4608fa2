#include "simulate_command.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/io/simulate_to_folder.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fssim {

namespace {

// "trial 3/10" on a terminal, for runs of several trials.
void show_progress_on_terminal(fss::SimulationOptions& options) {
  if (options.trials <= 1 || !::isatty(STDERR_FILENO)) return;
  options.trial_callback = [](int done, int total) {
    fss::write_stderr("\rfssim: trial " + std::to_string(done) + "/" + std::to_string(total) +
                      (done == total ? "\n" : ""));
  };
}

void print_metric(const char* label, double value) { std::printf("%s: %f\n", label, value); }

// The sensor line, only for an enabled sensor (docs/method.md §10).
void print_sensor(const fss::SensorModel& s) {
  if (!s.enabled()) return;
  const std::string full_well =
      s.full_well_electrons ? fss::format_number(*s.full_well_electrons) + " e-" : "none";
  const std::string adc = s.adc_bits != 0
                              ? std::to_string(s.adc_bits) + " bits, gain " +
                                    fss::format_number(s.adc_gain_electrons_per_count) + " e-/count"
                              : "none";
  std::printf("Sensor: read noise %s e-, dark current %s e-/slot, full well %s, ADC %s\n",
              fss::format_number(s.read_noise_electrons).c_str(),
              fss::format_number(s.dark_current_electrons_per_slot).c_str(), full_well.c_str(),
              adc.c_str());
}

// The restoration line, only for a restoration other than the inverse filter (docs/method.md §12).
void print_restoration(const fss::RestorationSummary& r) {
  if (r.options.method == fss::RestorationMethod::kInverse) return;
  std::string text = fss::describe(r.options);
  if (r.regularization && !r.options.regularization) {
    text += ": lambda " + fss::format_number(*r.regularization) +
            " minimises this run's expected error (an oracle: it knows the image)";
  }
  if (r.prior_level) {
    text += ": level c " + fss::format_number(*r.prior_level) +
            " gray levels^2 rad/px, fitted to a calibration observation";
  }
  if (r.noise_variance) text += ", noise variance " + fss::format_number(*r.noise_variance);
  std::printf("Restoration: %s\n", text.c_str());
}

// Under a velocity distribution (docs/method.md §13): the distribution and the first trial's
// velocity, whose images and metrics follow.
void print_velocity_distribution(const fss::SimulationReport& report) {
  const auto& d = report.options.velocity_distribution;
  if (!d) return;
  std::printf(
      "Velocity distribution: %s (%s); trial 1 at velocity %g (the images and metrics "
      "below)\n",
      fss::escape_control_characters(d->describe()).c_str(),
      fss::escape_control_characters(d->text()).c_str(), fss::first_trial_velocity(report.options));
}

// Under a velocity distribution: the trials' mean MSE against the predicted expected MSE (the
// mean RMSE is not sqrt(E[MSE]), Jensen), with the quadrature's cost and error estimate.
void print_mse_comparison(const fss::SimulationReport& report) {
  const fss::TrialStatistics& t = report.trials;
  if (!report.options.velocity_distribution || !t.mse_mean) return;
  if (t.n > 1) {
    std::printf("MSE mean over trials: %f (sd %f, se %f)", *t.mse_mean, t.mse_sd.value_or(0.0),
                t.mse_sd.value_or(0.0) / std::sqrt(static_cast<double>(t.n)));
  } else {
    std::printf("MSE of the one trial: %f", *t.mse_mean);
  }
  const fss::Prediction& p = report.prediction;
  if (p.finite && p.mse) {
    std::printf(
        "; predicted expected MSE: %f (sqrt: %f; %d evaluation%s, quadrature error "
        "estimate %g)\n",
        *p.mse, p.rmse, p.mse_evaluations, p.mse_evaluations == 1 ? "" : "s", p.mse_error_estimate);
  } else {
    std::printf("; predicted expected MSE: infinite: %s\n", p.mse_infinite_reason.c_str());
  }
}

// The predicted error (docs/method.md §6b, §6, §13).
void print_prediction(const fss::SimulationReport& report) {
  const fss::Prediction& p = report.prediction;
  const bool distribution = report.options.velocity_distribution.has_value();
  if (p.finite) {
    // The exact expectation (docs/method.md §6b), then the paper's stationary
    // approximation and the image-independent figure of merit (§6).
    std::printf("%s: %f (noise-free %f, noise %f)%s\n",
                distribution ? "Predicted sqrt(expected MSE)" : "Predicted RMSE", p.rmse,
                p.rmse_noise_free, p.noise,
                p.exact ? "" : ", approximate: the sensor clips readouts");
    if (report.restoration.options.method == fss::RestorationMethod::kInverse) {
      std::printf("Stationary approximation: RMSE %f (noise %f), SNR at level 100 %f\n",
                  p.rmse_stationary, p.sigma, p.snr_level100);
    } else {
      std::printf("Stationary approximation: RMSE %f (noise %f)\n", p.rmse_stationary, p.sigma);
    }
  } else if (distribution) {
    std::printf("Predicted RMSE: infinite: %s\n", p.mse_infinite_reason.c_str());
  } else {
    std::printf("Predicted RMSE: none (code not invertible, min |K| = %g at xi = %g)\n",
                report.kernel.min_abs, report.kernel.min_abs_xi);
  }
}

void print_results(const fss::SimulationReport& report, const fss::SimulationOptions& options,
                   const std::string& outdir) {
  print_velocity_distribution(report);
  print_metric("RMSE", report.metrics.rmse);
  print_metric("PSNR", report.metrics.psnr);
  print_metric("Contrast Invariant RMSE", report.metrics.rmse_ci);
  print_metric("Contrast Invariant PSNR", report.metrics.psnr_ci);
  if (report.metrics.ssim) {
    print_metric("SSIM", *report.metrics.ssim);
  } else {
    std::printf("SSIM: none (it needs an RMSE margin of at least 5 and at least 11 rows)\n");
  }
  print_restoration(report.restoration);
  print_prediction(report);
  const fss::TrialStatistics& t = report.trials;
  if (t.n > 1) {
    std::printf("Trials: %d, RMSE mean %f sd %f, RMSE_CI mean %f sd %f", t.n, t.rmse_mean,
                t.rmse_sd, t.rmse_ci_mean, t.rmse_ci_sd);
    if (t.ssim_mean) std::printf(", SSIM mean %f sd %f", *t.ssim_mean, t.ssim_sd.value_or(0.0));
    std::printf("\n");
  }
  print_mse_comparison(report);
  if (options.restore_velocity_px_per_slot && options.velocity_distribution) {
    std::printf("Restore velocity: %g (true velocity drawn by each trial)\n",
                *options.restore_velocity_px_per_slot);
  } else if (options.restore_velocity_px_per_slot) {
    std::printf("Restore velocity: %g (true velocity %g)\n", *options.restore_velocity_px_per_slot,
                options.velocity_px_per_slot);
  }
  print_sensor(options.sensor);
  std::printf("Seed: %llu\n", static_cast<unsigned long long>(options.seed));
  const fss::Geometry& g = report.geometry;
  std::printf(
      "Geometry: blur length %d, output %dx%d (input columns %d..%d), RMSE columns [%d, %d)\n",
      g.blur_length, g.output_width, report.height, 3 * g.half_blur,
      3 * g.half_blur + g.output_width - 1, report.rmse_first, report.rmse_end);
  std::printf("Outputs: %s\n", outdir.c_str());
}

// The outputs are in place; a script reading the metrics must still learn
// that they were not printed (a full disk, a closed stdout).
int flush_results() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    report_error(std::string("cannot write the results to standard output: ") +
                 std::strerror(errno));
    return kExitRuntime;
  }
  return kExitSuccess;
}

}  // namespace

SimulateCommand::SimulateCommand(CLI::App& app) : Command(app) {
  // Required unless a subcommand runs instead (checked in Run).
  input_option_ = app.add_option("-i,--input", input_,
                                 "input image: PNG (8/16-bit gray, RGB, palette) or TIFF (8/16-bit "
                                 "or 32-bit float, gray or RGB); alpha ignored; required without "
                                 "a subcommand")
                      ->check(not_empty());
  flags_.AddAll(app);
  app.add_option("-o,--outdir", outdir_, "output directory, created if missing")
      ->check(not_empty())
      ->capture_default_str();
  app.add_flag("--no-plots", no_plots_, "do not draw code.png and spectrum.png");
  app.add_flag("--sheet", output_options_.sheet,
               "also write sheet.png: observed | restored | residual side by side");
  app.add_flag("--report", output_options_.html_report,
               "also write report.html: parameters, metrics, images and plots on one page");
  app.add_flag("--save-float", output_options_.float_outputs,
               "also write observed.tif, restored.tif and residual.tif: 32-bit float, unclamped, "
               "residual not stretched");
  app.add_option("--png-depth", png_depth_,
                 "bits a sample of observed, restored, groundtruth and residual.png: 8, 16 (value "
                 "x 257), or auto (16 for a 16-bit or float input)")
      ->check(CLI::IsMember({"8", "16", "auto"}))
      ->capture_default_str();
}

int SimulateCommand::Run() const {
  if (input_option_->count() == 0) {
    report_error("--input is required (or a subcommand: code, sweep, spectra; see fssim --help)");
    return kExitUsage;
  }
  ErrorContext context{" (raise it with --max-memory)", ""};
  return run_reporting_errors([&] { return Simulate(&context); }, &context);
}

int SimulateCommand::Simulate(ErrorContext* context) const {
  fss::SimulationOptions options = flags_.Options();
  const std::string& code_name = flags_.code_name();
  context->activity = "reading code '" + code_name + "'";
  const fss::ShutterCode code = fss::load_code(code_name, "--code");
  show_progress_on_terminal(options);
  fss::FolderRunOptions run;
  run.outputs = output_options_;
  run.outputs.plots = !no_plots_;
  if (png_depth_ == "auto") {
    run.image_depth_from_input = true;
  } else {
    run.outputs.image_depth = *fss::png_depth_from_string(png_depth_);
  }
  const std::vector<std::string> builtins = fss::builtin_code_names();
  if (std::find(builtins.begin(), builtins.end(), code_name) == builtins.end()) {
    run.outputs.other_inputs.push_back(code_name);  // an input too: never overwritten
  }
  run.on_stage = [context](const std::string& stage) { context->activity = stage; };
  run.on_simulated = [](const fss::SimulationReport& report) {
    for (const auto& warning : report.warnings) {
      fss::write_stderr("fssim: warning: " + fss::escape_control_characters(warning) + "\n");
    }
  };
  const fss::SimulationReport report = fss::SimulateToFolder(input_, code, outdir_, options, run);
  print_results(report, options, outdir_);
  return flush_results();
}

}  // namespace fssim
