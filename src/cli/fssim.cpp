// fssim: the command line over the fss library. It parses options, loads the
// image and the code, calls fss::Simulate and writes the outputs.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "cli_common.h"
#include "code_commands.h"
#include "fss/code.h"
#include "fss/error.h"
#include "fss/outputs.h"
#include "fss/png_io.h"
#include "fss/simulate.h"
#include "sweep_command.h"

namespace {

using fssim::at_least;
using fssim::kExitRuntime;
using fssim::kExitUsage;
using fssim::kFinite;
using fssim::kPositive;

void print_metric(const char* label, double value) { std::printf("%s: %f\n", label, value); }

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

  // Required unless a subcommand is given (checked after parsing).
  app.add_option("-i,--input", input,
                 "input PNG image (8/16-bit gray, RGB, palette; alpha ignored); required "
                 "without a subcommand");
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

  // Subcommands: code design and sweeps (src/cli/code_commands.cpp, sweep_command.cpp).
  app.require_subcommand(0, 1);
  const fssim::CodeCommands code_commands(app);
  const fssim::SweepCommand sweep_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string message = e.what();
    std::cerr << "fssim: error: " << message << " (see " << fssim::help_hint(app) << ")\n";
    return kExitUsage;
  }
  if (!app.get_subcommands().empty()) {
    if (const std::string option = fssim::first_given_option(app); !option.empty()) {
      std::cerr << "fssim: error: " << option << " is an option of the simulation, not of '"
                << app.get_subcommands().front()->get_name()
                << "'; put the subcommand's options after its name (see " << fssim::help_hint(app)
                << ")\n";
      return kExitUsage;
    }
    return code_commands.parsed() ? code_commands.Run() : sweep_command.Run();
  }
  if (app.count("--input") == 0) {
    std::cerr << "fssim: error: --input is required (or a subcommand: code, sweep; see fssim "
                 "--help)\n";
    return kExitUsage;
  }
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
    fss::write_outputs(outdir, report, input);

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
