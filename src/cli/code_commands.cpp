#include "code_commands.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "cli_common.h"
#include "fss/model/code.h"
#include "fss/core/error.h"

namespace fssim {

namespace {

const char kFamilies[] = "sinc, mip, random, snapshot, accumulation";

std::string gain_domain(const fss::GenerateOptions& options) {
  return options.analog ? "[0, 1)" : "[-1, 1)";
}

// The comment line that opens a generated code file.
std::string generate_header(const fss::GenerateOptions& o) {
  const std::string family = fss::to_string(o.family);
  std::string text = "# " + family + " code, L = " + std::to_string(o.length);
  std::string command = "fssim code generate " + family + " --length " + std::to_string(o.length);
  if (o.family == fss::CodeFamily::kSinc || o.family == fss::CodeFamily::kMip) {
    text += ", designed for velocity " + format_number(o.velocity_px_per_slot) + ", dt " +
            format_number(o.dt);
    command +=
        " --velocity " + format_number(o.velocity_px_per_slot) + " --dt " + format_number(o.dt);
  } else if (o.family == fss::CodeFamily::kRandom) {
    text += ", gains uniform on " + gain_domain(o) + ", seed " + std::to_string(o.seed);
    command += " --seed " + std::to_string(o.seed) + (o.analog ? " --analog" : "");
  }
  return text + " (" + command + ")\n";
}

// The analysis grid in words, for the M line.
std::string grid_description(int grid) {
  if (grid == 0) {
    return std::to_string(2 * fss::kBandGridPoints) + "-node midpoint rule on [-pi, pi]";
  }
  return std::to_string(grid) + "-point DFT grid";
}

nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json analysis_json(const fss::ShutterCode& code, const fss::CodeAnalysis& a) {
  nlohmann::json j;
  j["code"] = {{"name", code.name}, {"length", a.length}, {"gains", code.gains}};
  j["parameters"] = {{"mode", fss::to_string(a.mode)},
                     {"velocity", a.velocity},
                     {"dt", a.dt},
                     {"snr", a.snr},
                     {"grid", a.grid == 0 ? "midpoint" : "dft"},
                     {"grid_points", a.grid == 0 ? 2 * fss::kBandGridPoints : a.grid}};
  j["analysis"] = {{"sum", a.sum},
                   {"square_sum", a.square_sum},
                   {"normalized_l1", a.normalized_l1},
                   {"k0", a.k0},
                   {"min_abs", a.min_abs},
                   {"min_abs_xi", a.min_abs_xi},
                   {"invertible", a.invertible},
                   {"q", a.q},
                   {"m", finite_or_null(a.m)},
                   {"noise_figure", finite_or_null(a.noise_figure)},
                   {"snr_level100", a.snr_level100},
                   {"snapshot_snr_level100", a.snapshot_snr_level100},
                   {"ratio_to_snapshot", a.ratio_to_snapshot},
                   {"snr_level100_bound", finite_or_null(a.snr_level100_bound)}};
  return j;
}

// Usage error unless 0 < |v| dt < 2, naming the options.
void check_design_band(double velocity, double dt, const std::string& what) {
  if (!fss::design_band_is_valid(velocity, dt)) {
    fss::throw_usage_error("--velocity " + format_number(velocity) + " with --dt " +
                           format_number(dt) + ": " + what +
                           " needs 0 < |velocity| dt < 2, got |velocity| dt = " +
                           format_number(std::abs(velocity) * dt));
  }
}

bool admissible(const std::vector<double>& gains, fss::ShutterMode mode, bool binary,
                double min_light = 0.0) {
  if (fss::gain_sum(gains) < min_light) return false;
  for (const double g : gains) {
    if (binary && g != 0.0 && g != 1.0) return false;
    if (mode == fss::ShutterMode::kAnalog && !(g >= 0.0 && g <= 1.0)) return false;
  }
  return true;
}

}  // namespace

CodeCommands::CodeCommands(CLI::App& app) {
  code_ = app.add_subcommand("code", "design shutter codes: generate, analyze, optimize");
  // At most one; none is reported in Run(), so that an unknown word after
  // `code` is named in the error instead of "a subcommand is required".
  code_->require_subcommand(0, 1);

  // generate
  generate_ = code_->add_subcommand(
      "generate",
      "write a code: sinc, mip (SPEC 7 constructions for |v| dt), random, snapshot "
      "or accumulation");
  generate_->add_option("FAMILY", family_, std::string("code family: ") + kFamilies)
      ->required()
      ->check(CLI::IsMember({"sinc", "mip", "random", "snapshot", "accumulation"}));
  generate_->add_option("-L,--length", generate_options_.length, "number of gains L")
      ->required()
      ->check(at_least(1));
  generate_
      ->add_option("-v,--velocity", generate_options_.velocity_px_per_slot,
                   "sinc, mip: velocity the code is designed for (pixels per slot)")
      ->check(finite())
      ->capture_default_str();
  generate_->add_option("--dt", generate_options_.dt, "sinc, mip: time slot length, > 0")
      ->check(finite() & positive())
      ->capture_default_str();
  generate_->add_option("--seed", generate_options_.seed, "random: seed of the gains")
      ->capture_default_str();
  generate_->add_flag("--analog", generate_options_.analog,
                      "random: gains on [0, 1) (analog) instead of [-1, 1)");
  generate_->add_option("-o,--output", generate_output_,
                        "code file to write (default: standard output)");

  // analyze
  analyze_ = code_->add_subcommand(
      "analyze",
      "figures of merit of a code without simulating an image: sums, min |K|, "
      "M, SNR at level 100 and its ratio to the snapshot's");
  analyze_
      ->add_option("CODE", analyze_code_,
                   "a built-in code (snapshot, accumulation, raskar, random, mip, sinc) or a "
                   "code file")
      ->required();
  analyze_->add_option("-v,--velocity", analyze_velocity_, "velocity in pixels per time slot")
      ->check(finite())
      ->capture_default_str();
  analyze_->add_option("--dt", analyze_dt_, "time slot length, > 0")
      ->check(finite() & positive())
      ->capture_default_str();
  analyze_->add_option("--snr", analyze_snr_, "SNR of a level-100 landscape seen through one slot")
      ->check(finite() & positive())
      ->capture_default_str();
  analyze_->add_option("-m,--mode", analyze_mode_, "numerical or analog (Q and admissible gains)")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  analyze_
      ->add_option("--grid", analyze_grid_,
                   "M on the N-point DFT grid (the simulator uses N = 2 (W - B)); 0: an " +
                       std::to_string(2 * fss::kBandGridPoints) + "-node midpoint rule")
      ->check(at_least(0))
      ->capture_default_str();
  analyze_->add_option("--json", analyze_json_, "also write the analysis as JSON to this file");

  // optimize
  optimize_ = code_->add_subcommand(
      "optimize", "search the code of length L that maximizes the SNR at level 100 at a velocity");
  fss::OptimizeOptions& o = optimize_options_;
  optimize_->add_option("-L,--length", o.length, "number of gains L")
      ->required()
      ->check(at_least(1));
  optimize_->add_option("-v,--velocity", o.velocity_px_per_slot, "velocity in pixels per slot")
      ->required()
      ->check(finite());
  optimize_->add_option("--dt", o.dt, "time slot length, > 0")
      ->check(finite() & positive())
      ->capture_default_str();
  optimize_->add_option("--snr", o.snr, "snr of the reported SNR at level 100 (scales it only)")
      ->check(finite() & positive())
      ->capture_default_str();
  optimize_
      ->add_option("-m,--mode", optimize_mode_,
                   "numerical (any real gains) or analog (gains in [0, 1])")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  optimize_->add_flag("--binary", o.binary, "gains in {0, 1} (the Agrawal-Raskar search space)");
  optimize_
      ->add_option("--min-light", o.min_light_slots,
                   "light budget for analog or binary codes: sum of gains >= this (slots)")
      ->check(finite())
      ->capture_default_str();
  optimize_->add_option("--restarts", o.restarts, "random starting codes (seeded by --seed)")
      ->check(at_least(0))
      ->capture_default_str();
  optimize_
      ->add_option("--iterations", o.max_iterations,
                   "per start: quasi-Newton iterations, or moves of the binary search")
      ->check(at_least(1))
      ->capture_default_str();
  optimize_->add_option("--seed", o.seed, "seed of the random starts")->capture_default_str();
  optimize_->add_option("-o,--output", optimize_output_, "code file to write the optimum to");
}

bool CodeCommands::parsed() const { return code_->parsed(); }

int CodeCommands::Run() const {
  return run_reporting_errors([this] {
    if (generate_->parsed()) return RunGenerate();
    if (analyze_->parsed()) return RunAnalyze();
    if (optimize_->parsed()) return RunOptimize();
    fss::throw_usage_error(
        "code needs a subcommand: generate, analyze or optimize (see fssim code --help)");
  });
}

int CodeCommands::RunGenerate() const {
  fss::GenerateOptions options = generate_options_;
  options.family = *fss::code_family_from_string(family_);
  if (options.family == fss::CodeFamily::kSinc || options.family == fss::CodeFamily::kMip) {
    check_design_band(options.velocity_px_per_slot, options.dt, "the " + family_ + " code");
  }
  if (options.length > fss::kMaxGeneratedCodeLength) {
    fss::throw_usage_error("--length " + std::to_string(options.length) + ": at most " +
                           std::to_string(fss::kMaxGeneratedCodeLength) + " gains");
  }
  const fss::ShutterCode code = fss::generate_code(options);
  const std::string text = generate_header(options) + fss::format_code_txt(code);
  if (generate_output_.empty()) {
    std::cout << text;
  } else {
    write_file_atomically(generate_output_, text);
    std::printf("%s code, L = %d: written to %s\n", family_.c_str(), options.length,
                generate_output_.c_str());
  }
  return 0;
}

int CodeCommands::RunAnalyze() const {
  const fss::ShutterCode code = fss::load_code(analyze_code_);
  const fss::ShutterMode mode = *fss::shutter_mode_from_string(analyze_mode_);
  const fss::CodeAnalysis a = fss::analyze_code(code, analyze_velocity_, analyze_dt_,
                                                analyze_snr_, mode, analyze_grid_);
  if (!analyze_json_.empty()) {
    write_file_atomically(analyze_json_, analysis_json(code, a).dump(2) + "\n");
  }
  std::printf("Code: %s (L = %d)\n", code.name.c_str(), a.length);
  std::printf("Setting: %s mode, velocity %g, dt %g, snr %g\n", analyze_mode_.c_str(), a.velocity,
              a.dt, a.snr);
  std::printf("Sum of gains: %f\n", a.sum);
  std::printf("Sum of squares: %f\n", a.square_sum);
  std::printf("Normalized L1 norm: %f\n", a.normalized_l1);
  std::printf("Min |K| on the band: %g at xi = %f\n", a.min_abs, a.min_abs_xi);
  std::printf("Invertible: %s\n", a.invertible ? "yes" : "no (K vanishes on the band)");
  std::printf("Q: %f\n", a.q);
  if (std::isfinite(a.m)) {
    std::printf("M (mean of 1/|K|^2, %s): %f\n", grid_description(a.grid).c_str(), a.m);
  } else {
    std::printf("M (mean of 1/|K|^2, %s): infinite\n", grid_description(a.grid).c_str());
  }
  std::printf("SNR at level 100: %f\n", a.snr_level100);
  std::printf("Snapshot SNR at level 100: %f\n", a.snapshot_snr_level100);
  std::printf("Ratio to the snapshot: %f\n", a.ratio_to_snapshot);
  if (std::isfinite(a.snr_level100_bound)) {
    std::printf("Bound on the SNR at level 100 (any code, any length): %f\n", a.snr_level100_bound);
  } else {
    std::printf("Bound on the SNR at level 100 (any code, any length): none at v = 0\n");
  }
  return 0;
}

int CodeCommands::RunOptimize() const {
  fss::OptimizeOptions options = optimize_options_;
  options.mode = *fss::shutter_mode_from_string(optimize_mode_);
  check_design_band(options.velocity_px_per_slot, options.dt, "the optimizer");
  if (options.length > fss::kMaxOptimizedCodeLength) {
    fss::throw_usage_error("--length " + std::to_string(options.length) + ": at most " +
                           std::to_string(fss::kMaxOptimizedCodeLength) + " gains");
  }
  if (options.min_light_slots != 0.0) {
    if (options.mode == fss::ShutterMode::kNumerical && !options.binary) {
      fss::throw_usage_error("--min-light " + format_number(options.min_light_slots) +
                             ": a light budget needs --mode analog or --binary (numerical "
                             "frames always gather L slots of light)");
    }
    if (!(options.min_light_slots >= 0.0 && options.min_light_slots <= options.length)) {
      fss::throw_usage_error("--min-light " + format_number(options.min_light_slots) +
                             ": must lie in [0, --length " + std::to_string(options.length) + "]");
    }
  }
  const fss::OptimizationResult result = fss::optimize_code(options);
  const fss::CodeAnalysis& a = result.analysis;

  if (!optimize_output_.empty()) {
    std::ostringstream header;
    header << "# optimized " << (options.binary ? "binary" : optimize_mode_)
           << " code, L = " << options.length << ", velocity "
           << format_number(options.velocity_px_per_slot) << ", dt " << format_number(options.dt)
           << ": SNR at level 100 " << format_number(a.snr_level100) << " at snr "
           << format_number(options.snr) << " (snapshot " << format_number(a.snapshot_snr_level100)
           << ")\n";
    fss::ShutterCode code{"optimized", result.gains};
    write_file_atomically(optimize_output_, header.str() + fss::format_code_txt(code));
  }
  std::cout << result.FullReport();

  // The paper's codes that the mode admits, at the same velocity and dt.
  std::printf("Paper codes (L = 52) admissible for %s gains%s, at the same velocity and dt:\n",
              options.binary ? "binary" : optimize_mode_.c_str(),
              options.min_light_slots > 0.0 ? " and the light budget" : "");
  std::string skipped;
  for (const std::string& name : fss::builtin_code_names()) {
    const fss::ShutterCode paper_code = *fss::builtin_code(name);
    const std::vector<double>& gains = paper_code.gains;
    if (!admissible(gains, options.mode, options.binary, options.min_light_slots)) {
      skipped += (skipped.empty() ? "" : ", ") + name;
      continue;
    }
    const fss::CodeAnalysis paper = fss::analyze_code(paper_code, options.velocity_px_per_slot,
                                                      options.dt, options.snr, options.mode);
    if (paper.invertible) {
      std::printf("  %-13s SNR at level 100 %9.4f  (optimized / paper: %.4f)\n", name.c_str(),
                  paper.snr_level100, a.snr_level100 / paper.snr_level100);
    } else {
      std::printf("  %-13s SNR at level 100 %9.4f  (not invertible)\n", name.c_str(),
                  paper.snr_level100);
    }
  }
  if (!skipped.empty()) std::printf("  (not admissible: %s)\n", skipped.c_str());
  std::printf("Gains:");
  for (const double g : result.gains) std::printf(" %.4g", g);
  std::printf("\n");
  if (!optimize_output_.empty()) std::printf("Code written to %s\n", optimize_output_.c_str());
  return 0;
}

}  // namespace fssim
