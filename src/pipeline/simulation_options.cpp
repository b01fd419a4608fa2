#include "fss/pipeline/simulation_options.h"

#include <cmath>
#include <string>

#include "core/enum_names.h"
#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/option_rules.h"

namespace fss {

namespace {
constexpr detail::EnumNames<NoiseModel, 3> kNoiseModelNames{
    {{NoiseModel::kPoisson, "poisson"},
     {NoiseModel::kNone, "none"},
     {NoiseModel::kAggregated, "aggregated"}}};
}  // namespace

std::string to_string(NoiseModel noise) { return detail::enum_name(kNoiseModelNames, noise); }

std::optional<NoiseModel> noise_model_from_string(std::string_view text) {
  return detail::enum_from_name(kNoiseModelNames, text);
}

namespace {

// The rules of a velocity distribution: valid on its own, and velocity_px_per_slot left at its
// default; "" when there is none or it keeps them.
std::string distribution_error(const SimulationOptions& o) {
  if (!o.velocity_distribution) return "";
  if (const std::string rule = distribution_velocity_rule(o.velocity_px_per_slot); !rule.empty()) {
    return "velocity_px_per_slot = " + format_exact(o.velocity_px_per_slot) + ": " + rule;
  }
  std::string distribution_error;
  if (!o.velocity_distribution->IsValid(&distribution_error)) {
    return "velocity_distribution: " + distribution_error;
  }
  return "";
}

// Under a velocity distribution, a restoration fitted to the run is refused.
std::string distribution_restoration_error(const SimulationOptions& o) {
  if (!o.velocity_distribution) return "";
  const RestorationOptions& r = o.restoration;
  const bool fitted = r.method == RestorationMethod::kWiener ||
                      (r.method == RestorationMethod::kTikhonov && !r.regularization);
  const std::string rule = distribution_restoration_rule(fitted);
  return rule.empty() ? "" : "restoration = " + describe(r) + ": " + rule;
}

// The rules of the sensor and the restoration, as parts of a simulation: "" when they hold.
std::string parts_error(const SimulationOptions& o) {
  std::string part_error;
  if (!o.sensor.IsValid(&part_error)) return "sensor." + part_error;
  if (!o.restoration.IsValid(&part_error)) return "restoration." + part_error;
  if (o.restoration.prior_level) {
    return "restoration.prior_level = " + format_exact(*o.restoration.prior_level) +
           ": a simulation estimates the power-law prior's level from a calibration "
           "observation; give the prior without a level (power-law or power-law:GAMMA)";
  }
  return distribution_restoration_error(o);
}

}  // namespace

bool SimulationOptions::IsValid(std::string* error) const {
  // True, with the message, when `rule` (option_rules.h) is broken.
  const auto broken = [&](const char* field, const std::string& value, const std::string& rule) {
    if (rule.empty()) return false;
    if (error) *error = std::string(field) + " = " + value + ": " + rule;
    return true;
  };
  if (broken("velocity_px_per_slot", format_exact(velocity_px_per_slot),
             velocity_rule(velocity_px_per_slot))) {
    return false;
  }
  if (restore_velocity_px_per_slot &&
      broken("restore_velocity_px_per_slot", format_exact(*restore_velocity_px_per_slot),
             velocity_rule(*restore_velocity_px_per_slot))) {
    return false;
  }
  if (const std::string message = distribution_error(*this); !message.empty()) {
    if (error) *error = message;
    return false;
  }
  // The sign of either scale is reported before the range of either.
  for (const bool positive : {false, true}) {
    if (scale_is_positive(dt) == positive && broken("dt", format_exact(dt), scale_rule(dt))) {
      return false;
    }
    if (scale_is_positive(snr) == positive && broken("snr", format_exact(snr), scale_rule(snr))) {
      return false;
    }
  }
  if (const std::string message = parts_error(*this); !message.empty()) {
    if (error) *error = message;
    return false;
  }
  const std::string margin = std::to_string(rmse_margin_columns);
  return !(broken("noise", to_string(noise),
                  noise_rule(noise == NoiseModel::kAggregated, mode == ShutterMode::kAnalog)) ||
           broken("noise", to_string(noise),
                  sensor_noise_rule(noise == NoiseModel::kAggregated, sensor.linear())) ||
           broken("rmse_margin_columns", margin, margin_rule(rmse_margin_columns)) ||
           broken("trials", std::to_string(trials), trials_rule(trials)) ||
           broken("threads", std::to_string(threads), threads_rule(threads)));
}

// Simulate, sweep, campaign, code analyze and the plots (spectra) all apply this check.
void check_code_for_mode(const ShutterCode& code, ShutterMode mode) {
  if (code.gains.empty())
    throw_usage_error("code '" + escape_control_characters(code.name) + "' has no gains");
  if (code.gains.size() > static_cast<std::size_t>(kMaxCodeLength)) {
    throw_usage_error("code '" + escape_control_characters(code.name) + "' has " +
                      std::to_string(code.gains.size()) + " gains, more than " +
                      std::to_string(kMaxCodeLength) + " (the longest code fssim analyses)");
  }
  for (std::size_t k = 0; k < code.gains.size(); ++k) {
    if (!std::isfinite(code.gains[k])) {
      throw_usage_error("code '" + escape_control_characters(code.name) + "': gain " +
                        std::to_string(k) + " is " + format_exact(code.gains[k]) +
                        ", gains must be finite");
    }
  }
  const double largest = gain_max_abs(code.gains);
  if (largest == 0.0) {
    throw_usage_error("code '" + escape_control_characters(code.name) +
                      "' has only zero gains: its transfer function is 0 and nothing is observed");
  }
  // sup |alpha| in [1e-100, 1e100] (L <= 1024): sum alpha, sum alpha^2 and
  // |K| stay finite and nonzero, as dt and snr do within the same range.
  if (const std::string rule = scale_rule(largest); !rule.empty()) {
    throw_usage_error("code '" + escape_control_characters(code.name) + "': its largest |gain| " +
                      format_exact(largest) + " is out of range: it " + rule +
                      " (scale the gains)");
  }
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < code.gains.size(); ++k) {
      const double g = code.gains[k];
      if (!(g >= 0.0 && g <= 1.0)) {
        throw_usage_error("code '" + escape_control_characters(code.name) +
                          "' cannot be used in analog mode: gain " + std::to_string(k) + " is " +
                          format_exact(g) +
                          ", analog gains must lie in [0, 1] (use --mode numerical)");
      }
    }
  }
}

}  // namespace fss
