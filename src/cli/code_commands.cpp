#include "code_commands.h"

#include <cmath>
#include <string>
#include <utility>

#include "cli_common.h"
#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/restoration.h"

namespace fssim {

namespace {

CLI::App& add_code_command(CLI::App& app) {
  CLI::App* code = app.add_subcommand("code", "design shutter codes: generate, analyze, optimize");
  // At most one; none is reported in Run(), so that an unknown word after
  // `code` is named in the error instead of "a subcommand is required".
  code->require_subcommand(0, 1);
  return *code;
}

}  // namespace

void SensorFlags::Add(CLI::App* app) {
  app->add_option("--read-noise", read_noise_,
                  "read noise, electrons RMS per readout (numerical: every frame, weighted by "
                  "its gain squared; analog: one readout), 0 to 1e100; 0: none")
      ->capture_default_str();
  app->add_option("--dark-current", dark_current_,
                  "dark current, electrons per unit slot (a frame's readout has dt, the analog "
                  "exposure L dt), 0 to 1e100; its mean is subtracted, its noise stays; 0: none")
      ->capture_default_str();
  app->add_option("--adc-bits", adc_bits_,
                  "ADC resolution in bits, 1 to 32 (its rounding counts G^2 / 12 per readout); "
                  "0: no ADC")
      ->capture_default_str();
  app->add_option("--adc-gain", adc_gain_,
                  "ADC gain G, electrons per count, > 0 and at most 1e100 (with --adc-bits)");
  app->add_option("--full-well", full_well_,
                  "refused here: the figure of merit is linear in the charge (simulate the "
                  "camera to see saturation)");
}

fss::SensorModel SensorFlags::Model(const std::string& command) const {
  if (full_well_) {
    fss::throw_usage_error("--full-well " + format_number(*full_well_) + ": " + command +
                           " computes a figure of merit linear in the charge; a full well "
                           "clips it (simulate the camera to see saturation)");
  }
  check_adc_gain(adc_gain_.has_value(), adc_bits_);
  fss::SensorModel sensor;
  sensor.read_noise_electrons = read_noise_;
  sensor.dark_current_electrons_per_slot = dark_current_;
  sensor.adc_bits = adc_bits_;
  if (adc_gain_) sensor.adc_gain_electrons_per_count = *adc_gain_;
  check_sensor_options(sensor);
  return sensor;
}

void RestorationFlags::Add(CLI::App* app) {
  const std::string default_prior = "power-law:2:" + format_exact(fss::kDefaultPriorLevel);
  const std::string lambda_range = "[" + format_exact(fss::kMinRegularization) + ", " +
                                   format_exact(fss::kMaxRegularization) + "]";
  app->add_option("--restoration", method_,
                  "the restoration the figure of merit assumes: inverse (the paper's inverse "
                  "filter), wiener (with --prior) or tikhonov (with --regularization)")
      ->check(CLI::IsMember({"inverse", "wiener", "tikhonov"}))
      ->capture_default_str();
  prior_option_ = app->add_option("--prior", prior_,
                                  "wiener only: power-law[:GAMMA[:C]], the prior S(xi) = C "
                                  "|xi|^-GAMMA of a landscape at mean level 100, GAMMA in [0, 8], "
                                  "C in [1e-100, 1e100]")
                      ->default_str(default_prior);
  regularization_option_ =
      app->add_option("--regularization", regularization_,
                      "tikhonov only: lambda in " + lambda_range +
                          " (mu = lambda (dt sum |alpha|)^2), or optimal: the lambda in that "
                          "range minimising the figure")
          ->capture_default_str();
}

fss::RestorationOptions RestorationFlags::Options() const {
  fss::RestorationOptions r;
  r.method = *fss::restoration_method_from_string(method_);
  if (prior_option_->count() > 0) {
    const std::string given = "--prior " + fss::shorten_for_message(prior_);
    if (r.method != fss::RestorationMethod::kWiener) {
      fss::throw_usage_error(
          given + ": only --restoration wiener takes a prior (this is " + method_ +
          (r.method == fss::RestorationMethod::kTikhonov ? ", whose bias uses the default prior)"
                                                         : ")"));
    }
    if (prior_ == "oracle") {
      fss::throw_usage_error(given +
                             ": code design has no image, so no oracle spectrum; use "
                             "power-law[:GAMMA[:C]]");
    }
    std::string error;
    if (!fss::parse_prior(prior_, &r, &error)) {
      // parse_prior's "prior '...': why (expected ...)", without the oracle in the expected forms
      if (const std::size_t at = error.find(" (expected"); at != std::string::npos) {
        error.erase(at);
      }
      fss::throw_usage_error("--" + error + " (expected power-law[:GAMMA[:C]])");
    }
  }
  if (regularization_option_->count() > 0) {
    const std::string given = "--regularization " + fss::shorten_for_message(regularization_);
    if (r.method != fss::RestorationMethod::kTikhonov) {
      fss::throw_usage_error(
          given + ": only --restoration tikhonov takes a regularization (this is " + method_ + ")");
    }
    if (regularization_ != "optimal") {
      const double lambda = fss::parse_finite_number(regularization_);
      if (!(lambda >= fss::kMinRegularization && lambda <= fss::kMaxRegularization)) {
        fss::throw_usage_error(given + ": must be a number in [" +
                               format_exact(fss::kMinRegularization) + ", " +
                               format_exact(fss::kMaxRegularization) + "] or optimal");
      }
      r.regularization = lambda;
    }
  }
  std::string error;
  if (!r.IsValid(&error)) fss::throw_usage_error(error);
  return r;
}

void check_design_band(double velocity, double dt, const std::string& what) {
  if (!fss::design_band_is_valid(velocity, dt)) {
    fss::throw_usage_error("--velocity " + format_exact(velocity) + " with --dt " +
                           format_exact(dt) + ": " + what +
                           " needs 0 < |velocity| dt < 2, got |velocity| dt = " +
                           format_exact(std::abs(velocity) * dt));
  }
}

void add_velocity_distribution_option(CLI::App* app, std::string* spec, CLI::Option** option) {
  *option = app->add_option(
      "--velocity-distribution", *spec,
      "instead of --velocity, a distribution of velocities (px per slot): uniform:LO:HI, "
      "normal:MEAN:SD (truncated at MEAN +/- 4 SD), normal:MEAN:SD:LO:HI, or a file of "
      "'velocity weight' lines; the figure of merit is the expected error over it, each "
      "velocity restored at itself");
}

std::optional<fss::VelocityDistribution> design_velocity_distribution(
    const CLI::Option* option, const std::string& spec, const CLI::Option* velocity_option,
    double dt) {
  if (option->count() == 0) return std::nullopt;
  if (velocity_option->count() > 0) {
    fss::throw_usage_error(
        "--velocity-distribution and --velocity are exclusive: the distribution gives the "
        "velocities");
  }
  fss::VelocityDistribution d = fss::load_velocity_distribution(spec, "--velocity-distribution");
  const double reach = d.max_abs_velocity() * dt;
  if (!(reach < 2.0)) {
    fss::throw_usage_error("--velocity-distribution " + fss::shorten_for_message(spec) +
                           " with --dt " + format_exact(dt) +
                           ": code design needs |v| dt < 2 at every velocity of the support [" +
                           format_exact(d.low) + ", " + format_exact(d.high) +
                           "], which reaches |v| dt = " + format_exact(reach));
  }
  return d;
}

CodeCommands::CodeCommands(CLI::App& parent)
    : Command(add_code_command(parent)), generate_(app()), analyze_(app()), optimize_(app()) {}

int CodeCommands::Run() const {
  return run_reporting_errors([this] {
    if (generate_.parsed()) return generate_.Run();
    if (analyze_.parsed()) return analyze_.Run();
    if (optimize_.parsed()) return optimize_.Run();
    fss::throw_usage_error(
        "code needs a subcommand: generate, analyze or optimize (see fssim code --help)");
  });
}

}  // namespace fssim
