// `fssim code optimize`.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "code_commands.h"
#include "fss/core/error.h"
#include "fss/model/code.h"

namespace fssim {

namespace {

bool admissible(const std::vector<double>& gains, fss::ShutterMode mode, bool binary,
                double min_light) {
  if (fss::gain_sum(gains) < min_light) return false;
  for (const double g : gains) {
    if (binary && g != 0.0 && g != 1.0) return false;
    if (mode == fss::ShutterMode::kAnalog && !(g >= 0.0 && g <= 1.0)) return false;
  }
  return true;
}

// The command line's own words for what OptimizeOptions::IsValid refuses.
void check_options(const fss::OptimizeOptions& options) {
  if (!options.velocity_distribution) {
    check_design_band(options.velocity_px_per_slot, options.dt, "the optimizer");
  } else if (options.velocity_distribution->is_point()) {
    const fss::VelocityDistribution& d = *options.velocity_distribution;
    const double v =
        d.kind == fss::VelocityDistributionKind::kDiscrete ? d.points[0].velocity : d.low;
    if (!fss::design_band_is_valid(v, options.dt)) {
      fss::throw_usage_error("--velocity-distribution " + fss::shorten_for_message(d.text()) +
                             " is the one velocity " + format_exact(v) + " with --dt " +
                             format_exact(options.dt) +
                             ": the optimizer needs 0 < |velocity| dt < 2");
    }
  }
  // c = v_r / snr^2 (fss::readout_noise_slots) beyond double precision
  if (!std::isfinite(fss::readout_noise_slots(options.sensor,
                                              static_cast<std::size_t>(options.length), options.dt,
                                              options.mode, options.snr))) {
    fss::throw_usage_error("--snr " + format_exact(options.snr) + " with the sensor's " +
                           fss::describe_design_sensor(options.sensor) +
                           ": its readout noise is more than 1e308 slots of level-100 light, "
                           "beyond double precision; lower --read-noise, --dark-current or "
                           "--adc-gain, or raise --snr");
  }
  if (options.length > fss::kMaxOptimizedCodeLength) {
    fss::throw_usage_error("--length " + std::to_string(options.length) + ": at most " +
                           std::to_string(fss::kMaxOptimizedCodeLength) + " gains");
  }
  if (options.min_light_slots == 0.0) return;
  if (options.mode == fss::ShutterMode::kNumerical && !options.binary) {
    fss::throw_usage_error("--min-light " + format_exact(options.min_light_slots) +
                           ": a light budget needs --mode analog or --binary (numerical "
                           "frames always gather L slots of light)");
  }
  if (!(options.min_light_slots >= 0.0 && options.min_light_slots <= options.length)) {
    fss::throw_usage_error("--min-light " + format_exact(options.min_light_slots) +
                           ": must lie in [0, --length " + std::to_string(options.length) + "]");
  }
}

// The paper's codes that the mode admits, at the same velocity (or distribution) and dt.
void print_paper_comparison(const fss::OptimizeOptions& options, const std::string& kind,
                            const fss::CodeAnalysis& ours) {
  std::printf("Paper codes (L = 52) admissible for %s gains%s, %s and dt:\n", kind.c_str(),
              options.min_light_slots > 0.0 ? " and the light budget" : "",
              options.velocity_distribution ? "under the same velocity distribution"
                                            : "at the same velocity");
  std::string skipped;
  for (const std::string& name : fss::builtin_code_names()) {
    const fss::ShutterCode paper_code = *fss::builtin_code(name);
    if (!admissible(paper_code.gains, options.mode, options.binary, options.min_light_slots)) {
      skipped += (skipped.empty() ? "" : ", ") + name;
      continue;
    }
    const fss::CodeAnalysis paper =
        options.velocity_distribution
            ? fss::analyze_code(paper_code, *options.velocity_distribution, options.dt, options.snr,
                                options.mode, 0, options.sensor, options.restoration)
            : fss::analyze_code(paper_code, options.velocity_px_per_slot, options.dt, options.snr,
                                options.mode, 0, options.sensor, options.restoration);
    // A Wiener or Tikhonov restoration has a finite figure for every code.
    if (paper.invertible || options.restoration.method != fss::RestorationMethod::kInverse) {
      std::printf("  %-13s SNR at level 100 %9.4f  (optimized / paper: %.4f)\n", name.c_str(),
                  paper.snr_level100, ours.snr_level100 / paper.snr_level100);
    } else {
      std::printf("  %-13s SNR at level 100 %9.4f  (not invertible)\n", name.c_str(),
                  paper.snr_level100);
    }
  }
  if (!skipped.empty()) std::printf("  (not admissible: %s)\n", skipped.c_str());
}

}  // namespace

CodeOptimizeCommand::CodeOptimizeCommand(CLI::App& code)
    : Command(code, "optimize",
              "search the code of length L that maximizes the SNR at level 100 at a velocity") {
  CLI::App& optimize = app();
  fss::OptimizeOptions& o = options_;
  optimize.add_option("-L,--length", o.length, "number of gains L")->required()->check(at_least(1));
  velocity_option_ =
      optimize
          .add_option("-v,--velocity", o.velocity_px_per_slot,
                      "velocity in pixels per slot (required unless --velocity-distribution)")
          ->check(finite());
  add_velocity_distribution_option(&optimize, &velocity_distribution_,
                                   &velocity_distribution_option_);
  optimize.add_option("--dt", o.dt, "time slot length, > 0")->check(scale())->capture_default_str();
  optimize
      .add_option("--snr", o.snr,
                  "SNR of a level-100 landscape seen through one slot: scales the reported SNR "
                  "only, unless a sensor option adds readout noise (which counts against "
                  "snr^2 / 100 photo-electrons per gray level)")
      ->check(scale())
      ->capture_default_str();
  optimize.add_option("-m,--mode", mode_, "numerical (any real gains) or analog (gains in [0, 1])")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  optimize.add_flag("--binary", o.binary, "gains in {0, 1} (the Agrawal-Raskar search space)");
  optimize
      .add_option("--min-light", o.min_light_slots,
                  "light budget for analog or binary codes: sum of gains >= this (slots)")
      ->check(finite())
      ->capture_default_str();
  optimize
      .add_option(
          "--restarts", o.restarts,
          "random starting codes (seeded by --seed), at most " + std::to_string(fss::kMaxRestarts))
      ->check(integer_in(0, fss::kMaxRestarts))
      ->capture_default_str();
  optimize
      .add_option("--iterations", o.max_iterations,
                  "per start: quasi-Newton iterations, or moves of the binary search; at most " +
                      std::to_string(fss::kMaxIterations))
      ->check(integer_in(1, fss::kMaxIterations))
      ->capture_default_str();
  optimize.add_option("--seed", o.seed, "seed of the random starts")
      ->check(seed_value())
      ->capture_default_str();
  sensor_.Add(&optimize);
  restoration_.Add(&optimize);
  optimize.add_option("-o,--output", output_,
                      "code file to write the optimum to (-: standard output, without the "
                      "report)");
}

void CodeOptimizeCommand::WriteCode(const fss::OptimizeOptions& options,
                                    const fss::OptimizationResult& result) const {
  const fss::CodeAnalysis& a = result.analysis;
  std::ostringstream header;
  header << "# optimized " << (options.binary ? "binary" : mode_) << " code, L = " << options.length
         << ", "
         << (options.velocity_distribution
                 ? "velocity distribution " + options.velocity_distribution->text()
                 : "velocity " + format_number(options.velocity_px_per_slot))
         << ", dt " << format_number(options.dt) << ": SNR at level 100 "
         << format_number(a.snr_level100) << " at snr " << format_number(options.snr)
         << " (snapshot " << format_number(a.snapshot_snr_level100) << ")\n";
  if (options.sensor.enabled()) {
    header << "# sensor: " << fss::describe_design_sensor(options.sensor) << "\n";
  }
  if (options.restoration.method != fss::RestorationMethod::kInverse) {
    header << "# criterion: " << fss::describe_design_criterion(options.restoration) << "\n";
  }
  std::vector<std::string> inputs;
  if (options.velocity_distribution) {
    header << "# the SNR averaged over the velocity distribution, "
           << options.velocity_distribution->describe() << "; worst velocity "
           << format_number(a.worst_velocity) << " (SNR at level 100 "
           << format_number(a.worst_snr_level100) << ")\n";
    if (options.velocity_distribution->kind == fss::VelocityDistributionKind::kDiscrete) {
      inputs.push_back(velocity_distribution_);
    }
  }
  const fss::ShutterCode code{"optimized", result.gains};
  write_output(output_, header.str() + fss::format_code_txt(code), inputs);
}

int CodeOptimizeCommand::Run() const {
  fss::OptimizeOptions options = options_;
  options.velocity_distribution = design_velocity_distribution(
      velocity_distribution_option_, velocity_distribution_, velocity_option_, options.dt);
  if (!options.velocity_distribution && velocity_option_->count() == 0) {
    fss::throw_usage_error(
        "code optimize needs --velocity V or --velocity-distribution SPEC (see fssim code "
        "optimize --help)");
  }
  options.mode = *fss::shutter_mode_from_string(mode_);
  options.sensor = sensor_.Model("code optimize");
  options.restoration = restoration_.Options();
  check_options(options);
  const fss::OptimizationResult result = fss::optimize_code(options);
  if (!output_.empty()) WriteCode(options, result);
  if (is_stdout(output_)) return kExitSuccess;  // stdout holds the code file alone
  std::cout << result.FullReport();
  print_paper_comparison(options, options.binary ? "binary" : mode_, result.analysis);
  std::printf("Gains:");
  for (const double g : result.gains) std::printf(" %.4g", g);
  std::printf("\n");
  if (!output_.empty()) std::printf("Code written to %s\n", output_.c_str());
  return kExitSuccess;
}

}  // namespace fssim
