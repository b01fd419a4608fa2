#include "simulation_flags.h"

#include <unistd.h>

#include <cmath>
#include <limits>

#include "cli_common.h"
#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"

namespace fssim {

namespace {

constexpr long long kMaxInt = std::numeric_limits<int>::max();

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
    return "value '" + text + "' is not a memory size (e.g. 800M, 1.5G, 0 for no limit)";
  }
  // Below one byte it would silently mean no limit.
  if (value * scale < 1.0) {
    return "value '" + text + "' is less than one byte (0 means no limit)";
  }
  *bytes = static_cast<std::size_t>(value * scale);
  return {};
}

}  // namespace

void SimulationFlags::AddCode(CLI::App& app) {
  app.add_option("-c,--code", code_name_,
                 "shutter code: snapshot, accumulation, raskar, random, mip, sinc, or a code file")
      ->capture_default_str();
}

void SimulationFlags::AddMode(CLI::App& app) {
  add_checked_option(app, "-m,--mode", mode_,
                     "numerical (burst of frames, any real gains) or analog (gains in [0,1])",
                     CLI::IsMember({"numerical", "analog"}));
}

void SimulationFlags::AddVelocity(CLI::App& app) {
  velocity_option_ = add_checked_option(
      app, "-v,--velocity", options_.velocity_px_per_slot,
      "velocity in pixels per time slot, signed (direction along rows)", finite());
}

void SimulationFlags::AddVelocityDistribution(CLI::App& app) {
  velocity_distribution_option_ = app.add_option(
      "--velocity-distribution", velocity_distribution_,
      "each trial draws its velocity from uniform:LO:HI, normal:MEAN:SD (truncated at MEAN +/- 4 "
      "SD), normal:MEAN:SD:LO:HI or a file of 'velocity weight' lines; the geometry is that of "
      "the largest |v|, the prediction the expected MSE over it (docs/method.md §13); not with "
      "--velocity");
}

void SimulationFlags::AddRestoreVelocity(CLI::App& app) {
  restore_velocity_option_ =
      app.add_option("--restore-velocity", restore_velocity_,
                     "velocity assumed by the restoration (default: the true --velocity), to "
                     "measure the cost of a wrong velocity estimate")
          ->check(finite());
}

void SimulationFlags::AddDt(CLI::App& app) {
  add_checked_option(app, "--dt", options_.dt, "time slot length, > 0 (1e-100 to 1e100)", scale());
}

void SimulationFlags::AddSnr(CLI::App& app) {
  add_checked_option(app, "--snr", options_.snr,
                     "SNR of a level-100 landscape seen through one slot, > 0 (1e-100 to 1e100)",
                     scale());
}

void SimulationFlags::AddSeed(CLI::App& app) {
  add_checked_option(app, "--seed", options_.seed, "seed of the photon noise", seed_value());
}

void SimulationFlags::AddNoise(CLI::App& app) {
  add_checked_option(app, "--noise", noise_,
                     "poisson (every frame drawn), aggregated (numerical mode: each pixel's frames "
                     "of equal gains drawn as one exact Poisson variate, the others above 50 "
                     "photons as one normal of the same mean and variance, much faster), or none "
                     "for a noise-free run of the same pipeline",
                     CLI::IsMember({"poisson", "aggregated", "none"}));
}

void SimulationFlags::AddRmseMargin(CLI::App& app) {
  app.add_option("--rmse-margin", options_.rmse_margin_columns,
                 "columns left out at each side of the output for the RMSE (default 3B, B the blur "
                 "length), or auto: 3B where the image is wide enough (W >= 9B + 1), else the "
                 "largest margin leaving a window of B columns")
      ->transform(rmse_margin_value(false));
}

void SimulationFlags::AddTrials(CLI::App& app) {
  add_checked_option(app, "--trials", options_.trials,
                     "independent noise realizations (seeds seed, seed+1, ...)",
                     integer_in(1, kMaxInt));
}

void SimulationFlags::AddThreads(CLI::App& app) {
  add_checked_option(app, "--threads", options_.threads,
                     "worker threads, 0 = all cores (results do not depend on it)",
                     integer_in(0, kMaxInt));
}

void SimulationFlags::AddMaxMemory(CLI::App& app) {
  max_memory_option_ = app.add_option(
      "--max-memory", max_memory_,
      "refuse runs needing more memory than SIZE (e.g. 800M, 2G; 0: no limit; default: "
      "half of physical memory)");
}

void SimulationFlags::AddSensor(CLI::App& app) {
  fss::SensorModel& sensor = options_.sensor;
  app.add_option("--read-noise", sensor.read_noise_electrons,
                 "sensor read noise, electrons RMS per readout (numerical: every frame is read; "
                 "analog: one readout), 0 to 1e100; default 0 (off)")
      ->check(finite());
  app.add_option("--dark-current", sensor.dark_current_electrons_per_slot,
                 "sensor dark current, mean electrons per unit time slot, 0 to 1e100; its mean is "
                 "subtracted, its noise stays; default 0 (off)")
      ->check(finite());
  full_well_option_ =
      app.add_option("--full-well", full_well_,
                     "sensor full well, electrons: a readout's charge is clipped there (the "
                     "prediction is then approximate); default none")
          ->check(finite());
  adc_bits_option_ =
      app.add_option("--adc-bits", sensor.adc_bits,
                     "ADC resolution in bits, 1 to 32: readouts rounded to counts in [0, 2^B - 1]; "
                     "default 0 (no ADC)")
          ->check(integer_in(std::numeric_limits<int>::min(), kMaxInt));
  adc_gain_option_ =
      app.add_option("--adc-gain", sensor.adc_gain_electrons_per_count,
                     "ADC gain, electrons per count, > 0 and at most 1e100 (needs --adc-bits)")
          ->check(finite())
          ->capture_default_str();
}

void SimulationFlags::AddRestoration(CLI::App& app) {
  restoration_option_ = add_checked_option(
      app, "--restoration", restoration_,
      "inverse (the paper's inverse filter), tikhonov or wiener (docs/method.md §12)",
      CLI::IsMember({"inverse", "tikhonov", "wiener"}));
  regularization_option_ =
      app.add_option("--regularization", regularization_,
                     "tikhonov only: lambda in [1e-8, 1e2], or optimal (the lambda minimising "
                     "this run's exact expected error: an oracle, it knows the image)")
          ->capture_default_str();
  prior_option_ = app.add_option("--prior", prior_,
                                 "wiener only: power-law[:GAMMA] (S = c |xi|^-GAMMA, c and the "
                                 "noise estimated from a calibration observation) or oracle (the "
                                 "ground truth's own spectrum: it sees the image)")
                      ->capture_default_str();
}

void SimulationFlags::read_restoration(fss::SimulationOptions& options) const {
  fss::RestorationOptions& r = options.restoration;
  r.method = *fss::restoration_method_from_string(restoration_);
  const bool tikhonov = r.method == fss::RestorationMethod::kTikhonov;
  const bool wiener = r.method == fss::RestorationMethod::kWiener;
  if (regularization_option_->count() > 0 && !tikhonov) {
    fss::throw_usage_error("--regularization: only --restoration tikhonov takes it (this run is " +
                           restoration_ + ")");
  }
  if (prior_option_->count() > 0 && !wiener) {
    fss::throw_usage_error("--prior: only --restoration wiener takes it (this run is " +
                           restoration_ + ")");
  }
  if (tikhonov && regularization_ != "optimal") {
    const double lambda = fss::parse_finite_number(regularization_);
    if (std::isnan(lambda) || lambda < fss::kMinRegularization ||
        lambda > fss::kMaxRegularization) {
      fss::throw_usage_error("--regularization: value '" +
                             fss::shorten_for_message(regularization_) +
                             "' is not optimal or a number in [1e-8, 1e2]");
    }
    r.regularization = lambda;
  }
  std::string problem;
  if (wiener && !fss::parse_prior(prior_, &r, &problem)) {
    fss::throw_usage_error("--prior: " + problem);
  }
  if (r.prior_level) {
    fss::throw_usage_error("--prior: value '" + fss::shorten_for_message(prior_) +
                           "' gives a level; a simulation estimates it from a calibration "
                           "observation (give power-law or power-law:GAMMA)");
  }
}

void SimulationFlags::read_velocity_distribution(fss::SimulationOptions& options) const {
  if (velocity_distribution_option_->count() == 0) return;
  if (velocity_option_ != nullptr && velocity_option_->count() > 0) {
    fss::throw_usage_error(
        "--velocity-distribution: cannot be used with -v/--velocity (each trial draws its "
        "velocity from the distribution)");
  }
  const fss::RestorationOptions& r = options.restoration;
  const bool fitted = r.method == fss::RestorationMethod::kWiener ||
                      (r.method == fss::RestorationMethod::kTikhonov && !r.regularization);
  if (const std::string rule = fss::distribution_restoration_rule(fitted); !rule.empty()) {
    fss::throw_usage_error("--restoration " + fss::describe(r) + " " + rule);
  }
  options.velocity_distribution =
      fss::load_velocity_distribution(velocity_distribution_, "--velocity-distribution");
}

std::string SimulationFlags::velocity_distribution_file(
    const fss::SimulationOptions& options) const {
  const auto& d = options.velocity_distribution;
  return d && d->kind == fss::VelocityDistributionKind::kDiscrete ? d->source : std::string();
}

void SimulationFlags::AddAll(CLI::App& app) {
  AddCode(app);
  AddMode(app);
  AddVelocity(app);
  AddRestoreVelocity(app);
  AddVelocityDistribution(app);
  AddDt(app);
  AddSnr(app);
  AddSeed(app);
  AddNoise(app);
  AddRmseMargin(app);
  AddTrials(app);
  AddThreads(app);
  AddMaxMemory(app);
  AddSensor(app);
  AddRestoration(app);
}

fss::SimulationOptions SimulationFlags::Options() const {
  fss::SimulationOptions options = options_;
  if (max_memory_option_ != nullptr) options.max_memory_bytes = default_memory_limit();
  if (max_memory_option_ != nullptr && max_memory_option_->count() > 0) {  // "" too
    const std::string problem = parse_memory_size(max_memory_, &options.max_memory_bytes);
    if (!problem.empty())
      fss::throw_usage_error("--max-memory: " + problem + " (see fssim --help)");
  }
  if (restore_velocity_option_ != nullptr && restore_velocity_option_->count() > 0) {
    options.restore_velocity_px_per_slot = restore_velocity_;
  }
  options.mode = *fss::shutter_mode_from_string(mode_);
  options.noise = *fss::noise_model_from_string(noise_);
  const std::string noise_problem = fss::noise_rule(options.noise == fss::NoiseModel::kAggregated,
                                                    options.mode == fss::ShutterMode::kAnalog);
  if (!noise_problem.empty()) {
    fss::throw_usage_error("--noise: value " + noise_ + " " + noise_problem);
  }
  if (full_well_option_ != nullptr) check_sensor(options);
  if (restoration_option_ != nullptr) read_restoration(options);
  if (velocity_distribution_option_ != nullptr) read_velocity_distribution(options);
  return options;
}

void SimulationFlags::check_sensor(fss::SimulationOptions& options) const {
  if (full_well_option_->count() > 0) options.sensor.full_well_electrons = full_well_;
  check_adc_gain(adc_gain_option_->count() > 0, options.sensor.adc_bits);
  check_sensor_options(options.sensor);
  const std::string noise_problem = fss::sensor_noise_rule(
      options.noise == fss::NoiseModel::kAggregated, options.sensor.linear());
  if (!noise_problem.empty()) {
    fss::throw_usage_error("--noise: value " + noise_ + " " + noise_problem);
  }
}

}  // namespace fssim
