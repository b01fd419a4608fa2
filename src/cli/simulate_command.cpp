#include "simulate_command.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <iostream>
#include <optional>
#include <system_error>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/parallel.h"
#include "fss/io/image_io.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fssim {

namespace {

// code.png and spectrum.png need only the code and the motion: they are drawn
// on their own thread while the image is read and simulated. Not when
// --threads 1 asks for one thread or no thread starts (write_outputs draws
// them then), nor for a run Simulate will refuse: its error should not wait
// for them.
std::future<fss::RunPlots> start_plots(const fss::ShutterCode& code,
                                       const fss::SimulationOptions& options, bool plots) {
  if (!plots || !options.IsValid(nullptr) || fss::resolve_thread_count(options.threads) <= 1) {
    return {};
  }
  try {
    fss::check_code_for_mode(code, options.mode);
    return std::async(std::launch::async, fss::render_run_plots, code, options);
  } catch (const fss::Error&) {
    // Simulate reports it
  } catch (const std::system_error&) {
    // no thread: drawn by write_outputs
  }
  return {};
}

// The simulation plan (kernel analysis, filters, FFTW plans, noise weights:
// all that does not depend on the pixels) made on its own thread while the
// image is decoded, for a PNG whose header gives the width. Empty without a
// header, a second thread, or a plan: Simulate then makes the plan itself,
// and reports any error in its own order.
using EarlyPlan = std::future<std::optional<fss::SimulationPlan>>;
EarlyPlan start_plan(const std::optional<fss::PngHeaderSize>& size,
                     const fss::SimulationOptions& options, const fss::ShutterCode& code) {
  if (!size || size->width > fss::kMaxImageSide || size->height > fss::kMaxImageSide ||
      !options.IsValid(nullptr) || fss::resolve_thread_count(options.threads) <= 1) {
    return {};
  }
  const auto make = [options, code, width = size->width]() -> std::optional<fss::SimulationPlan> {
    try {
      return fss::SimulationPlan(options, width, code);
    } catch (const fss::Error&) {
      return std::nullopt;  // Simulate reports it
    }
  };
  try {
    return std::async(std::launch::async, make);
  } catch (const std::system_error&) {
    return {};  // no thread: Simulate makes the plan
  }
}

// Simulate, with the early plan when it fits the image.
fss::SimulationReport simulate_with(EarlyPlan& plan, const fss::SimulationOptions& options,
                                    const fss::Image& image, const fss::ShutterCode& code,
                                    fss::ObservedRowSink* sink) {
  const std::optional<fss::SimulationPlan> made = plan.valid() ? plan.get() : std::nullopt;
  if (made && made->fits(options, image.width, code)) {
    return fss::Simulate(*made, options, image, code, sink);
  }
  return fss::Simulate(options, image, code, sink);
}

// The size a PNG's header declares, when the file can hold it: a header
// declaring more pixels (at 1 bit each) than the file can hold after deflate
// (at most 1032 times) is corrupt, and read_png says so. Empty for anything
// else (read_png or read_image says what is wrong).
std::optional<fss::PngHeaderSize> plausible_png_header(const std::string& input) {
  const std::optional<fss::PngHeaderSize> size = fss::read_png_header_size(input);
  if (!size) return std::nullopt;
  std::error_code ec;
  const std::uintmax_t file_bytes = std::filesystem::file_size(input, ec);
  if (ec || static_cast<double>(size->width) * size->height / 8.0 >
                1032.0 * (static_cast<double>(file_bytes) + 1.0)) {
    return std::nullopt;
  }
  return size;
}

// --png-depth: 8, 16, or auto (16 for an input of more than 8 bits a sample).
fss::PngDepth resolve_png_depth(const std::string& choice, const fss::ImageFileInfo& input) {
  if (choice == "auto") return input.bits_per_sample > 8 ? fss::PngDepth::k16 : fss::PngDepth::k8;
  return *fss::png_depth_from_string(choice);
}

// Refuses, from the PNG header alone, a run the memory guard of Simulate
// would refuse after decoding (the same estimate: the header gives the
// channels and the bit depth): a huge image fails at once, before it is
// decoded.
void check_memory_from_header(const std::optional<fss::PngHeaderSize>& size,
                              const std::string& input, const fss::SimulationOptions& options,
                              const fss::ShutterCode& code, const fss::OutputOptions& outputs,
                              const std::string& png_depth) {
  if (options.max_memory_bytes == 0 || !size) return;
  fss::Geometry geometry;
  try {
    const double v = std::max(std::abs(options.velocity_px_per_slot),
                              std::abs(options.restore_velocity_px_per_slot.value_or(0.0)));
    geometry = fss::Geometry::compute(size->width, code.length(), v, options.dt);
  } catch (const fss::Error&) {
    return;  // Simulate reports it
  }
  // The outputs as the run will make them (the depth --png-depth gives this
  // input), so that this estimate is the one made after decoding.
  fss::OutputOptions resolved = outputs;
  resolved.image_depth =
      resolve_png_depth(png_depth, {fss::ImageFileFormat::kPng, size->bit_depth, false});
  const fss::ObservedPng8 sink(size->height, size->channels);  // allocates nothing yet
  const bool to_sink =
      !resolved.sheet && !resolved.float_outputs && resolved.image_depth == fss::PngDepth::k8;
  const std::size_t extra = fss::output_encoding_bytes_per_sample(resolved, size->channels);
  const std::size_t needed =
      fss::estimate_working_memory_bytes(size->width, size->height, size->channels, geometry,
                                         options, code.length(), to_sink ? &sink : nullptr, extra);
  if (needed > options.max_memory_bytes) {
    const auto sizes = fss::format_bytes_distinct(static_cast<double>(needed),
                                                  static_cast<double>(options.max_memory_bytes));
    fss::throw_limit_error(
        "input '" + input + "': a run on this " + std::to_string(size->width) + " x " +
        std::to_string(size->height) + " x " + std::to_string(size->channels) + " image" +
        (extra > 0 ? " with its extra outputs (sheet, report, float or 16-bit)" : "") +
        " needs about " + sizes.first + " of memory, more than the memory limit of " +
        sizes.second);
  }
}

// "trial 3/10" on a terminal, for runs of several trials.
void show_progress_on_terminal(fss::SimulationOptions& options) {
  if (options.trials <= 1 || !::isatty(STDERR_FILENO)) return;
  options.trial_callback = [](int done, int total) {
    fss::write_stderr("\rfssim: trial " + std::to_string(done) + "/" + std::to_string(total) +
                      (done == total ? "\n" : ""));
  };
}

std::string describe_simulation(const std::string& input, const fss::Image& image) {
  return "simulating input '" + input + "' (" + std::to_string(image.width) + "x" +
         std::to_string(image.height) + ", " + std::to_string(image.channels) +
         (image.channels == 1 ? " channel)" : " channels)");
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

void print_results(const fss::SimulationReport& report, const fss::SimulationOptions& options,
                   const std::string& outdir) {
  print_metric("RMSE", report.metrics.rmse);
  print_metric("PSNR", report.metrics.psnr);
  print_metric("Contrast Invariant RMSE", report.metrics.rmse_ci);
  print_metric("Contrast Invariant PSNR", report.metrics.psnr_ci);
  const fss::Prediction& p = report.prediction;
  if (p.finite) {
    // The exact expectation (docs/method.md §6b), then the paper's stationary
    // approximation and the image-independent figure of merit (§6).
    std::printf("Predicted RMSE: %f (noise-free %f, noise %f)%s\n", p.rmse, p.rmse_noise_free,
                p.noise, p.exact ? "" : ", approximate: the sensor clips readouts");
    std::printf("Stationary approximation: RMSE %f (noise %f), SNR at level 100 %f\n",
                p.rmse_stationary, p.sigma, p.snr_level100);
  } else {
    std::printf("Predicted RMSE: none (code not invertible, min |K| = %g at xi = %g)\n",
                report.kernel.min_abs, report.kernel.min_abs_xi);
  }
  const fss::TrialStatistics& t = report.trials;
  if (t.n > 1) {
    std::printf("Trials: %d, RMSE mean %f sd %f, RMSE_CI mean %f sd %f\n", t.n, t.rmse_mean,
                t.rmse_sd, t.rmse_ci_mean, t.rmse_ci_sd);
  }
  if (options.restore_velocity_px_per_slot) {
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
  fss::OutputOptions output_options = output_options_;
  output_options.plots = !no_plots_;
  const std::string& code_name = flags_.code_name();

  context->activity = "reading code '" + code_name + "'";
  const fss::ShutterCode code = fss::load_code(code_name, "--code");
  std::future<fss::RunPlots> plots = start_plots(code, options, output_options.plots);
  context->activity = "reading input '" + input_ + "'";
  const std::optional<fss::PngHeaderSize> header = plausible_png_header(input_);
  check_memory_from_header(header, input_, options, code, output_options, png_depth_);
  EarlyPlan plan = start_plan(header, options, code);
  fss::ImageFileInfo input_info;
  const fss::Image image = fss::read_image(input_, options.max_memory_bytes, &input_info);
  output_options.image_depth = resolve_png_depth(png_depth_, input_info);
  context->activity = describe_simulation(input_, image);
  show_progress_on_terminal(options);
  // An 8-bit observed.png is all fssim needs of the observed image unless
  // the sheet or observed.tif shows it: keep its rows as 8-bit samples, not
  // doubles.
  std::optional<fss::ObservedPng8> observed_png8;
  if (!output_options.sheet && !output_options.float_outputs &&
      output_options.image_depth == fss::PngDepth::k8) {
    observed_png8.emplace(image.height, image.channels);
  }
  fss::check_outputs_memory(options, image, code, output_options,
                            observed_png8 ? &*observed_png8 : nullptr);
  const fss::SimulationReport report =
      simulate_with(plan, options, image, code, observed_png8 ? &*observed_png8 : nullptr);
  for (const auto& warning : report.warnings) {
    fss::write_stderr("fssim: warning: " + fss::escape_control_characters(warning) + "\n");
  }
  // The plots are waited for by the files that show them, the image PNGs
  // made meanwhile; without a thread they are drawn when written.
  if (plots.valid()) output_options.plots_in_progress = plots.share();
  context->activity = "writing the outputs to '" + outdir_ + "'";
  const std::vector<std::string> builtins = fss::builtin_code_names();
  if (std::find(builtins.begin(), builtins.end(), code_name) == builtins.end()) {
    output_options.other_inputs.push_back(code_name);  // an input too: never overwritten
  }
  if (observed_png8) {
    fss::write_outputs(outdir_, report, *observed_png8, image, input_, output_options);
  } else {
    fss::write_outputs(outdir_, report, image, input_, output_options);
  }
  print_results(report, options, outdir_);
  return flush_results();
}

}  // namespace fssim
