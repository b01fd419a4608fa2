// fssim: the command line over the fss library. It parses options, loads the
// image and the code, calls fss::Simulate and writes the outputs.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "fss/code.h"
#include "fss/error.h"
#include "fss/kernel.h"
#include "fss/outputs.h"
#include "fss/plot.h"
#include "fss/png_io.h"
#include "fss/simulate.h"

namespace {

constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

// CLI11 validator for finite numbers (CLI11 accepts "nan" and "inf").
const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) {
        return "value " + text + " is not a finite number";
      }
      return {};
    },
    "FINITE", "finite");

const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0)) {
        return "value " + text + " must be > 0";
      }
      return {};
    },
    "POSITIVE", "positive");

// Integer option of at least `minimum`, with a short message (CLI11's own
// range checks print the largest double in full).
CLI::Validator at_least(long long minimum) {
  return CLI::Validator(
      [minimum](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < minimum) {
          return "value " + text + " must be an integer >= " + std::to_string(minimum);
        }
        return {};
      },
      ">=" + std::to_string(minimum));
}

void print_metric(const char* label, double value) { std::printf("%s: %f\n", label, value); }

// Options of `fssim spectra`: |K| of several codes on one plot.
struct SpectraCommand {
  std::vector<std::string> codes;
  double velocity = 1.0;
  double dt = 1.0;
  bool linear = false;
  std::string output;
  fss::PlotOptions plot{800, 420, ""};
};

int run_spectra(const SpectraCommand& command) {
  std::vector<fss::ShutterCode> codes;
  for (const std::string& name : command.codes) codes.push_back(fss::load_code(name));
  const std::vector<std::uint8_t> png = fss::plot_spectra_overlay_png(
      codes, command.velocity, command.dt, !command.linear, command.plot);
  fss::write_file_atomically(command.output, std::string(png.begin(), png.end()));
  for (const fss::ShutterCode& code : codes) {
    const fss::KernelAnalysis k = fss::analyze_kernel(code.gains, command.velocity, command.dt);
    std::printf("%s: min |K| %g at xi %g%s\n", code.name.c_str(), k.min_abs, k.min_abs_xi,
                k.invertible ? "" : " (not invertible)");
  }
  std::printf("Plot: %s\n", command.output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "fssim: flutter shutter camera simulator (Tendero, IPOL 2012). Simulates the motion-blurred, "
      "photon-noisy observation of an image through a flutter shutter code, restores it by "
      "inverse filtering, and measures and predicts the error.",
      "fssim"};
  app.set_version_flag("--version", std::string("fssim ") + FSS_VERSION);
  app.get_formatter()->column_width(32);

  std::string input;
  std::string code_name = "raskar";
  std::string mode_text = "numerical";
  std::string noise_text = "poisson";
  std::string outdir = "out";
  fss::SimulationOptions options;

  // Required unless a subcommand runs instead (checked after parsing).
  app.add_option("-i,--input", input,
                 "input PNG image, required (8/16-bit gray, RGB, palette; alpha ignored)");
  app.add_option("-c,--code", code_name,
                 "shutter code: snapshot, accumulation, raskar, random, mip, sinc, or a code file")
      ->capture_default_str();
  app.add_option("-m,--mode", mode_text,
                 "numerical (burst of frames, any real gains) or analog (gains in [0,1])")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  app.add_option("-v,--velocity", options.velocity_px_per_slot,
                 "velocity in pixels per time slot, signed (direction along rows)")
      ->check(kFinite)
      ->capture_default_str();
  app.add_option("--dt", options.dt, "time slot length, > 0")
      ->check(kFinite & kPositive)
      ->capture_default_str();
  app.add_option("--snr", options.snr, "SNR of a level-100 landscape seen through one slot, > 0")
      ->check(kFinite & kPositive)
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the photon noise")->capture_default_str();
  app.add_option("--noise", noise_text,
                 "poisson, or none for a noise-free run of the same pipeline")
      ->check(CLI::IsMember({"poisson", "none"}))
      ->capture_default_str();
  app.add_option(
         "--rmse-margin", options.rmse_margin_columns,
         "columns left out at each side of the output for the RMSE (default 3B, B the blur length)")
      ->check(at_least(0));
  app.add_option("--trials", options.trials,
                 "independent noise realizations (seeds seed, seed+1, ...)")
      ->check(at_least(1))
      ->capture_default_str();
  app.add_option("--threads", options.threads,
                 "worker threads, 0 = all cores (results do not depend on it)")
      ->check(at_least(0))
      ->capture_default_str();
  app.add_option("-o,--outdir", outdir, "output directory, created if missing")
      ->capture_default_str();
  fss::OutputOptions output_options;
  bool no_plots = false;
  app.add_flag("--no-plots", no_plots, "do not draw code.png and spectrum.png");
  app.add_flag("--sheet", output_options.sheet,
               "also write sheet.png: observed | restored | residual side by side");
  app.add_flag("--report", output_options.html_report,
               "also write report.html: parameters, metrics, images and plots on one page");

  SpectraCommand spectra;
  CLI::App* spectra_app =
      app.add_subcommand("spectra",
                         "plot |K| of several codes on one picture (no simulation): fssim spectra "
                         "--output FILE CODE...");
  spectra_app->add_option("codes", spectra.codes, "built-in code names or code files (1 to 8)")
      ->required();
  spectra_app->add_option("-o,--output", spectra.output, "PNG file to write")->required();
  spectra_app->add_option("-v,--velocity", spectra.velocity, "velocity in pixels per time slot")
      ->check(kFinite)
      ->capture_default_str();
  spectra_app->add_option("--dt", spectra.dt, "time slot length, > 0")
      ->check(kFinite & kPositive)
      ->capture_default_str();
  spectra_app->add_flag("--linear", spectra.linear, "linear |K| axis (default: logarithmic)");
  spectra_app->add_option("--width", spectra.plot.width, "plot width in pixels")
      ->check(CLI::Range(fss::kPlotMinSide, fss::kPlotMaxSide))
      ->capture_default_str();
  spectra_app->add_option("--height", spectra.plot.height, "plot height in pixels")
      ->check(CLI::Range(fss::kPlotMinSide, fss::kPlotMaxSide))
      ->capture_default_str();
  spectra_app->add_option("--title", spectra.plot.title,
                          "plot title (default: made from the data)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string message = e.what();
    std::cerr << "fssim: error: " << message << " (see fssim --help)\n";
    return kExitUsage;
  }
  if (spectra_app->parsed()) {
    try {
      return run_spectra(spectra);
    } catch (const fss::Error& e) {
      std::cerr << "fssim: error: " << e.what() << "\n";
      return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
    }
  }
  if (input.empty()) {
    std::cerr << "fssim: error: --input is required (see fssim --help)\n";
    return kExitUsage;
  }
  output_options.plots = !no_plots;
  options.mode = *fss::shutter_mode_from_string(mode_text);
  options.noise = *fss::noise_model_from_string(noise_text);

  try {
    const fss::ShutterCode code = fss::load_code(code_name);
    const fss::Image image = fss::read_png(input);
    const bool show_progress = options.trials > 1 && ::isatty(STDERR_FILENO);
    if (show_progress) {
      options.trial_callback = [](int done, int total) {
        std::fprintf(stderr, "\rfssim: trial %d/%d", done, total);
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
      };
    }
    const fss::SimulationReport report = fss::Simulate(options, image, code);
    for (const auto& warning : report.warnings) std::cerr << "fssim: warning: " << warning << "\n";
    fss::write_outputs(outdir, report, input, output_options);

    print_metric("RMSE", report.metrics.rmse);
    print_metric("PSNR", report.metrics.psnr);
    print_metric("Contrast Invariant RMSE", report.metrics.rmse_ci);
    print_metric("Contrast Invariant PSNR", report.metrics.psnr_ci);
    if (report.prediction.finite) {
      std::printf("Predicted RMSE: %f (noise-free %f, noise %f)\n", report.prediction.rmse,
                  report.prediction.rmse_noise_free, report.prediction.sigma);
    } else {
      std::printf("Predicted RMSE: none (code not invertible, min |K| = %g at xi = %g)\n",
                  report.kernel.min_abs, report.kernel.min_abs_xi);
    }
    if (report.trials.n > 1) {
      std::printf("Trials: %d, RMSE mean %f sd %f, RMSE_CI mean %f sd %f\n", report.trials.n,
                  report.trials.rmse_mean, report.trials.rmse_sd, report.trials.rmse_ci_mean,
                  report.trials.rmse_ci_sd);
    }
    std::printf("Seed: %llu\n", static_cast<unsigned long long>(options.seed));
    std::printf(
        "Geometry: blur length %d, output %dx%d (input columns %d..%d), RMSE columns [%d, %d)\n",
        report.geometry.blur_length, report.geometry.output_width, report.height,
        3 * report.geometry.half_blur,
        3 * report.geometry.half_blur + report.geometry.output_width - 1, report.rmse_first,
        report.rmse_end);
    std::printf("Outputs: %s\n", outdir.c_str());
    return 0;
  } catch (const fss::Error& e) {
    std::cerr << "fssim: error: " << e.what() << "\n";
    return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
  } catch (const std::bad_alloc&) {
    std::cerr << "fssim: error: out of memory\n";
    return kExitRuntime;
  } catch (const std::exception& e) {
    std::cerr << "fssim: error: " << e.what() << "\n";
    return kExitRuntime;
  }
}
