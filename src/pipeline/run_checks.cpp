#include "pipeline/run_checks.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/model/sensor.h"
#include "fss/model/transfer.h"

namespace fss {

// The dark charge of one readout, D = d * exposure, is drawn in double
// precision and subtracted again: its Poisson noise sqrt(D) is resolved in
// steps of ulp(D) ~ 2^-52 D, 2^-12 sqrt(D) at D = 1e24, and above about
// 2^104 ~ 2e31 it and the photo-electrons vanish in round-off (the
// observation comes out as 0). Refused above 1e24 e-.
namespace {

constexpr double kMaxDarkChargeElectrons = 1e24;

void check_dark_charge(const SimulationOptions& options, const ShutterCode& code) {
  const double exposure = readout_exposure_slots(code.gains.size(), options.dt, options.mode);
  const double charge = options.sensor.dark_current_electrons_per_slot * exposure;
  if (charge <= kMaxDarkChargeElectrons) return;
  throw_usage_error("dark current " + format_exact(options.sensor.dark_current_electrons_per_slot) +
                    " e-/slot over a readout's exposure of " + format_exact(exposure) +
                    " (dt; L dt in analog mode) is a dark charge of " + format_exact(charge) +
                    " e-, more than the " + format_number(kMaxDarkChargeElectrons) +
                    " e- whose Poisson noise double precision can resolve: lower the dark "
                    "current or dt");
}

// The power-law prior's noise is the model's at the level mean(observed) / K(0)
// (docs/method.md §12): a code of zero sum, K(0) = 0, observes no mean level.
void check_power_law_level(const SimulationOptions& options, const ShutterCode& code) {
  const RestorationOptions& r = options.restoration;
  if (r.method != RestorationMethod::kWiener || r.prior != PriorKind::kPowerLaw) return;
  const double k0 = options.dt * gain_sum(code.gains);
  if (!transfer_vanishes(std::abs(k0), transfer_scale(code.gains, options.dt))) return;
  throw_usage_error("code '" + escape_control_characters(code.name) +
                    "' has gains of zero sum, so K(0) = 0 and its observation has no mean level, "
                    "from which the power-law prior estimates the noise: use the oracle prior or "
                    "the tikhonov restoration");
}

}  // namespace

void check_run_settings(const SimulationOptions& options, const ShutterCode& code) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  check_code_for_mode(code, options.mode);
  check_dark_charge(options, code);
  check_power_law_level(options, code);
}

void check_inputs(const SimulationOptions& options, const Image& input, const ShutterCode& code) {
  check_run_settings(options, code);
  if (input.channels != 1 && input.channels != 3) {
    throw_usage_error("input has " + std::to_string(input.channels) +
                      " channels, expected 1 (gray) or 3 (RGB)");
  }
}

std::string restore_blur_excess(const SimulationOptions& options, int width, int code_length) {
  const double v = options.velocity_distribution ? options.velocity_distribution->max_abs_velocity()
                                                 : options.velocity_px_per_slot;
  const double v_r = options.restore_velocity_px_per_slot.value_or(v);
  if (!(std::abs(v_r) > std::abs(v))) return "";
  const double motion = std::ceil(std::abs(v_r) * options.dt * code_length);
  if (motion < static_cast<double>(width)) return "";
  return "over " + std::to_string(code_length) + " slots of dt " + format_exact(options.dt) +
         " spans " + format_exact(motion) + " pixels, more than the image width " +
         std::to_string(width);
}

double geometry_velocity(const SimulationOptions& options) {
  const double v = options.velocity_distribution ? options.velocity_distribution->max_abs_velocity()
                                                 : std::abs(options.velocity_px_per_slot);
  return std::max(v, std::abs(options.restore_velocity_px_per_slot.value_or(0.0)));
}

namespace {

// Under a velocity distribution (docs/method.md §13): B is the blur of the largest of the
// support's |v| and |v_r|, the same for every trial.
Geometry distribution_geometry(const SimulationOptions& options, int width,
                               const ShutterCode& code) {
  if (const std::string excess = restore_blur_excess(options, width, code.length());
      !excess.empty()) {
    throw_usage_error("the blur of restore velocity " +
                      format_exact(*options.restore_velocity_px_per_slot) + " " + excess);
  }
  const double v = geometry_velocity(options);
  const double motion = std::ceil(v * options.dt * code.length());
  if (!(motion < static_cast<double>(width))) {
    throw_usage_error("the blur of the largest |velocity| " + format_exact(v) +
                      " of the velocity distribution's support over " +
                      std::to_string(code.length()) + " slots of dt " + format_exact(options.dt) +
                      " spans " + format_exact(motion) + " pixels, more than the image width " +
                      std::to_string(width));
  }
  return Geometry::compute(width, code.length(), v, options.dt);
}

}  // namespace

Geometry run_geometry(const SimulationOptions& options, int width, const ShutterCode& code) {
  if (options.velocity_distribution) return distribution_geometry(options, width, code);
  const double v = options.velocity_px_per_slot;
  const double v_r = options.restore_velocity_px_per_slot.value_or(v);
  // A blur wider than the image is said to be the restore velocity's when
  // it is the larger (Geometry::compute would name "velocity").
  if (const std::string excess = restore_blur_excess(options, width, code.length());
      !excess.empty()) {
    throw_usage_error("the blur of restore velocity " + format_exact(v_r) + " " + excess);
  }
  return Geometry::compute(width, code.length(), std::abs(v_r) > std::abs(v) ? v_r : v, options.dt);
}

Geometry checked_geometry(const SimulationOptions& options, int width, const ShutterCode& code) {
  check_run_settings(options, code);
  const Geometry geometry = run_geometry(options, width, code);
  metric_windows(geometry, options.rmse_margin_columns);
  return geometry;
}

}  // namespace fss
