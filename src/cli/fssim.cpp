// fssim: the command line over the fss library. It parses options, loads the
// image and the code, calls fss::Simulate and writes the outputs.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <future>
#include <iostream>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "cli_common.h"
#include "code_commands.h"
#include "fss/core/error.h"
#include "fss/core/parallel.h"
#include "fss/io/outputs.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/simulate.h"
#include "sweep_command.h"

namespace {

constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

// Range of --dt and --snr: far enough from the limits of double precision
// that K, lambda2 = snr^2 / 100 and their products stay finite and nonzero.
constexpr double kSmallestScale = 1e-100;
constexpr double kLargestScale = 1e100;

void print_error(std::string_view message) {
  std::cerr << "fssim: error: " << fss::escape_control_characters(message) << std::endl;
}

// The validators are made inside run(), so that even their construction
// cannot throw outside main's handlers.

// A number > 0 within [kSmallestScale, kLargestScale].
CLI::Validator positive_scale() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0)) {
          return "value " + text + " must be > 0";
        }
        if (!(value >= kSmallestScale && value <= kLargestScale)) {
          return "value " + text + " is out of range: it must lie in [1e-100, 1e100]";
        }
        return {};
      },
      "POSITIVE", "positive");
}

// Integer option in [minimum, maximum], with a short message (CLI11's own
// range checks print the largest double in full).
CLI::Validator integer_in(long long minimum, long long maximum) {
  return CLI::Validator(
      [minimum, maximum](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < minimum || value > maximum) {
          return "value " + text + " must be an integer in [" + std::to_string(minimum) + ", " +
                 std::to_string(maximum) + "]";
        }
        return {};
      },
      "[" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]");
}

// --seed: decimal digits of an unsigned 64-bit integer. CLI11 itself wraps
// "-1" and saturates values above 2^64 - 1 without a word.
CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec != std::errc() || ptr != end) {
          return "value " + text + " must be an integer in [0, " +
                 std::to_string(std::numeric_limits<std::uint64_t>::max()) + "]";
        }
        return {};
      },
      "UINT64", "seed");
}

CLI::Validator not_empty() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return text.empty() ? std::string("the path must not be empty") : std::string();
      },
      "PATH", "not empty");
}

// Half of the physical memory, the default --max-memory.
std::size_t default_memory_limit() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size) / 2;
}

// --max-memory: "800M", "1.5G", "2048K", "123456" (bytes), "0" (no limit);
// K, M, G, T are powers of 1024. Empty on success, with `bytes` set.
std::string parse_memory_size(const std::string& text, std::size_t* bytes) {
  if (text == "0") {
    *bytes = 0;
    return {};
  }
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (...) {
    used = 0;
  }
  const std::string suffix = used == 0 ? std::string() : text.substr(used);
  double scale = 1.0;
  if (suffix == "K" || suffix == "k") scale = 1024.0;
  if (suffix == "M" || suffix == "m") scale = 1024.0 * 1024.0;
  if (suffix == "G" || suffix == "g") scale = 1024.0 * 1024.0 * 1024.0;
  if (suffix == "T" || suffix == "t") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  const bool suffix_ok = suffix.empty() || scale > 1.0;
  if (used == 0 || !suffix_ok || !std::isfinite(value) || value <= 0.0 || value * scale >= 1e18) {
    return "value " + text + " is not a memory size (e.g. 800M, 1.5G, 0 for no limit)";
  }
  *bytes = static_cast<std::size_t>(value * scale);
  return {};
}

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

void print_metric(const char* label, double value) { std::printf("%s: %f\n", label, value); }

int run(int argc, char** argv) {
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
                 "input PNG image (8/16-bit gray, RGB, palette; alpha ignored); required "
                 "without a subcommand")
      ->check(not_empty());
  app.add_option("-c,--code", code_name,
                 "shutter code: snapshot, accumulation, raskar, random, mip, sinc, or a code file")
      ->capture_default_str();
  app.add_option("-m,--mode", mode_text,
                 "numerical (burst of frames, any real gains) or analog (gains in [0,1])")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  app.add_option("-v,--velocity", options.velocity_px_per_slot,
                 "velocity in pixels per time slot, signed (direction along rows)")
      ->check(fssim::finite())
      ->capture_default_str();
  double restore_velocity = 0.0;
  CLI::Option* restore_velocity_option =
      app.add_option("--restore-velocity", restore_velocity,
                     "velocity assumed by the restoration (default: the true --velocity), to "
                     "measure the cost of a wrong velocity estimate")
          ->check(fssim::finite());
  app.add_option("--dt", options.dt, "time slot length, > 0 (1e-100 to 1e100)")
      ->check(fssim::finite() & positive_scale())
      ->capture_default_str();
  app.add_option("--snr", options.snr,
                 "SNR of a level-100 landscape seen through one slot, > 0 (1e-100 to 1e100)")
      ->check(fssim::finite() & positive_scale())
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the photon noise")
      ->check(seed_value())
      ->capture_default_str();
  app.add_option("--noise", noise_text,
                 "poisson, or none for a noise-free run of the same pipeline")
      ->check(CLI::IsMember({"poisson", "none"}))
      ->capture_default_str();
  app.add_option(
         "--rmse-margin", options.rmse_margin_columns,
         "columns left out at each side of the output for the RMSE (default 3B, B the blur length)")
      ->check(integer_in(0, fss::kMaxImageSide));
  app.add_option("--trials", options.trials,
                 "independent noise realizations (seeds seed, seed+1, ...)")
      ->check(integer_in(1, std::numeric_limits<int>::max()))
      ->capture_default_str();
  app.add_option("--threads", options.threads,
                 "worker threads, 0 = all cores (results do not depend on it)")
      ->check(integer_in(0, std::numeric_limits<int>::max()))
      ->capture_default_str();
  std::string max_memory_text;
  app.add_option("--max-memory", max_memory_text,
                 "refuse runs needing more memory than SIZE (e.g. 800M, 2G; 0: no limit; default: "
                 "half of physical memory)");
  app.add_option("-o,--outdir", outdir, "output directory, created if missing")
      ->check(not_empty())
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
      ->check(fssim::finite())
      ->capture_default_str();
  spectra_app->add_option("--dt", spectra.dt, "time slot length, > 0")
      ->check(fssim::finite() & positive_scale())
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

  // Subcommands: code design and sweeps (src/cli/code_commands.cpp, sweep_command.cpp).
  app.require_subcommand(0, 1);
  const fssim::CodeCommands code_commands(app);
  const fssim::SweepCommand sweep_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    print_error(std::string(e.what()) + " (see " + fssim::help_hint(app) + ")");
    return kExitUsage;
  } catch (const std::exception& e) {
    print_error(std::string(e.what()) + " (see fssim --help)");
    return kExitUsage;
  }
  if (!app.get_subcommands().empty()) {
    if (const std::string option = fssim::first_given_option(app); !option.empty()) {
      print_error(option + " is an option of the simulation, not of '" +
                  app.get_subcommands().front()->get_name() +
                  "'; put the subcommand's options after its name (see " + fssim::help_hint(app) +
                  ")");
      return kExitUsage;
    }
    if (spectra_app->parsed()) {
      try {
        return run_spectra(spectra);
      } catch (const fss::Error& e) {
        print_error(e.what());
        return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
      }
    }
    return code_commands.parsed() ? code_commands.Run() : sweep_command.Run();
  }
  if (app.count("--input") == 0) {
    print_error("--input is required (or a subcommand: code, sweep, spectra; see fssim --help)");
    return kExitUsage;
  }
  options.max_memory_bytes = default_memory_limit();
  if (!max_memory_text.empty()) {
    const std::string problem = parse_memory_size(max_memory_text, &options.max_memory_bytes);
    if (!problem.empty()) {
      print_error("--max-memory: " + problem + " (see fssim --help)");
      return kExitUsage;
    }
  }
  if (restore_velocity_option->count() > 0) options.restore_velocity_px_per_slot = restore_velocity;
  output_options.plots = !no_plots;
  options.mode = *fss::shutter_mode_from_string(mode_text);
  options.noise = *fss::noise_model_from_string(noise_text);

  // What is being done, for a failure that does not say it (out of memory).
  std::string activity = "reading code '" + code_name + "'";
  try {
    const fss::ShutterCode code = fss::load_code(code_name);
    // code.png and spectrum.png need only the code and the motion: draw them
    // on their own thread while the image is read and simulated (when
    // --threads 1 asks for one or no thread starts, write_outputs draws them).
    // Not for a run Simulate will refuse: its error should not wait for them.
    std::future<fss::RunPlots> plots;
    if (output_options.plots && options.IsValid(nullptr) &&
        fss::resolve_thread_count(options.threads) > 1) {
      try {
        fss::check_code_for_mode(code, options.mode);
        plots = std::async(std::launch::async, fss::render_run_plots, code, options);
      } catch (const fss::Error&) {
        // Simulate reports it
      } catch (const std::system_error&) {
        // no thread: drawn below
      }
    }
    activity = "reading input '" + input + "'";
    const fss::Image image = fss::read_png(input, options.max_memory_bytes);
    activity = "simulating input '" + input + "' (" + std::to_string(image.width) + "x" +
               std::to_string(image.height) + ", " + std::to_string(image.channels) +
               (image.channels == 1 ? " channel)" : " channels)");
    const bool show_progress = options.trials > 1 && ::isatty(STDERR_FILENO);
    if (show_progress) {
      options.trial_callback = [](int done, int total) {
        std::fprintf(stderr, "\rfssim: trial %d/%d", done, total);
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
      };
    }
    // observed.png is all fssim needs of the observed image unless the sheet
    // shows it: keep its rows as 8-bit samples, not doubles.
    std::optional<fss::ObservedPng8> observed_png8;
    if (!output_options.sheet) {
      observed_png8.emplace(image.height, image.channels);
    }
    const fss::SimulationReport report =
        fss::Simulate(options, image, code, observed_png8 ? &*observed_png8 : nullptr);
    for (const auto& warning : report.warnings) {
      std::cerr << "fssim: warning: " << fss::escape_control_characters(warning) << "\n";
    }
    activity = "drawing the plots";
    if (plots.valid()) output_options.rendered_plots = plots.get();  // else drawn when written
    activity = "writing the outputs to '" + outdir + "'";
    const std::vector<std::string> builtins = fss::builtin_code_names();
    if (std::find(builtins.begin(), builtins.end(), code_name) == builtins.end()) {
      output_options.other_inputs.push_back(code_name);  // an input too: never overwritten
    }
    if (observed_png8) {
      fss::write_outputs(outdir, report, *observed_png8, image, input, output_options);
    } else {
      fss::write_outputs(outdir, report, image, input, output_options);
    }

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
    if (options.restore_velocity_px_per_slot) {
      std::printf("Restore velocity: %g (true velocity %g)\n",
                  *options.restore_velocity_px_per_slot, options.velocity_px_per_slot);
    }
    std::printf("Seed: %llu\n", static_cast<unsigned long long>(options.seed));
    std::printf(
        "Geometry: blur length %d, output %dx%d (input columns %d..%d), RMSE columns [%d, %d)\n",
        report.geometry.blur_length, report.geometry.output_width, report.height,
        3 * report.geometry.half_blur,
        3 * report.geometry.half_blur + report.geometry.output_width - 1, report.rmse_first,
        report.rmse_end);
    std::printf("Outputs: %s\n", outdir.c_str());
    // The outputs are in place; a script reading the metrics must still learn
    // that they were not printed (a full disk, a closed stdout).
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      print_error(std::string("cannot write the results to standard output: ") +
                  std::strerror(errno));
      return kExitRuntime;
    }
    return 0;
  } catch (const fss::Error& e) {
    print_error(std::string(e.what()) +
                (e.kind() == fss::ErrorKind::kLimit ? " (raise it with --max-memory)" : ""));
    return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
  } catch (const std::bad_alloc&) {
    print_error("out of memory while " + activity);
    return kExitRuntime;
  } catch (const std::exception& e) {
    print_error(std::string(e.what()) + " (while " + activity + ")");
    return kExitRuntime;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Beyond a file size limit (ulimit -f), a write must fail with EFBIG, which
  // is reported and cleaned up, rather than kill the process mid-write.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    print_error("out of memory");
  } catch (const std::exception& e) {
    print_error(e.what());
  } catch (...) {
    print_error("unexpected failure");
  }
  return kExitRuntime;
}
