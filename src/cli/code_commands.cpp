#include "code_commands.h"

#include <cmath>
#include <string>
#include <utility>

#include "cli_common.h"
#include "fss/core/error.h"

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

void check_design_band(double velocity, double dt, const std::string& what) {
  if (!fss::design_band_is_valid(velocity, dt)) {
    fss::throw_usage_error("--velocity " + format_exact(velocity) + " with --dt " +
                           format_exact(dt) + ": " + what +
                           " needs 0 < |velocity| dt < 2, got |velocity| dt = " +
                           format_exact(std::abs(velocity) * dt));
  }
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
