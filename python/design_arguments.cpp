#include "design_arguments.h"

#include <array>
#include <string_view>
#include <utility>

#include "arguments.h"
#include "fss/core/error.h"

namespace fss::python {

namespace {

using Names = std::pair<std::string_view, std::string_view>;

// Longer fields first: "restoration.prior_exponent" before "restoration.prior".
constexpr std::array<Names, 13> kDesignNames = {{
    {"sensor.read_noise_electrons", "read_noise"},
    {"sensor.dark_current_electrons_per_slot", "dark_current"},
    {"sensor.full_well_electrons", "full_well"},
    {"sensor.adc_gain_electrons_per_count", "adc_gain"},
    {"sensor.adc_bits", "adc_bits"},
    {"read_noise_electrons", "read_noise"},
    {"dark_current_electrons_per_slot", "dark_current"},
    {"adc_gain_electrons_per_count", "adc_gain"},
    {"restoration.regularization", "regularization"},
    {"restoration.prior_exponent", "prior"},
    {"restoration.prior_level", "prior"},
    {"restoration.prior", "prior"},
    {"regularization", "regularization"},
}};

std::string quoted(std::string_view text) {
  std::string quoted_text(1, '\'');
  quoted_text += shorten_for_message(text);
  quoted_text += '\'';
  return quoted_text;
}

}  // namespace

std::string design_field_names(const std::string& message) {
  return rename_field(message, kDesignNames);
}

SensorModel design_sensor(const DesignSensorArguments& a) {
  if (a.full_well) {
    throw_usage_error("full_well = " + format_exact(*a.full_well) +
                      ": code design computes a figure of merit linear in the charge, which a "
                      "full well clips (simulate the camera, fss.simulate(full_well=...), to "
                      "see saturation)");
  }
  SensorModel sensor;
  sensor.read_noise_electrons = a.read_noise;
  sensor.dark_current_electrons_per_slot = a.dark_current;
  sensor.adc_bits = int_argument("adc_bits", a.adc_bits, 0, 32);
  if (a.adc_gain && sensor.adc_bits == 0) {
    throw_usage_error("adc_gain: needs adc_bits (without an ADC there are no counts)");
  }
  sensor.adc_gain_electrons_per_count = a.adc_gain.value_or(1.0);
  std::string error;
  if (!sensor.IsValid(&error)) throw_usage_error(design_field_names(error));
  return sensor;
}

namespace {

// Wiener's prior into `r`: any power law, never the oracle (code design has no image).
void design_prior(const std::string& text, RestorationOptions& r) {
  if (r.method != RestorationMethod::kWiener) {
    throw_usage_error("prior = " + quoted(text) + ": only restoration='wiener' takes a prior (" +
                      (r.method == RestorationMethod::kTikhonov
                           ? "this is tikhonov, whose bias uses the default prior)"
                           : "this is inverse)"));
  }
  if (text == "oracle") {
    throw_usage_error(
        "prior = 'oracle': code design has no image, so no oracle spectrum; use "
        "'power-law[:GAMMA[:C]]'");
  }
  std::string error;
  if (!parse_prior(text, &r, &error)) {
    // parse_prior's "prior '...': why (expected ...)", with the forms code design takes
    if (const std::size_t at = error.find(" (expected"); at != std::string::npos) error.erase(at);
    throw_usage_error(error + " (expected 'power-law[:GAMMA[:C]]')");
  }
}

}  // namespace

RestorationOptions design_restoration(const DesignRestorationArguments& a) {
  const std::optional<RestorationMethod> method = restoration_method_from_string(a.method);
  if (!method) {
    throw_usage_error("restoration: " + quoted(a.method) +
                      " is not 'inverse', 'tikhonov' or 'wiener'");
  }
  RestorationOptions r;
  r.method = *method;
  if (a.prior) design_prior(*a.prior, r);
  if (a.regularization || a.regularization_optimal) {
    if (r.method != RestorationMethod::kTikhonov) {
      throw_usage_error("regularization: only restoration='tikhonov' takes it (this is " +
                        a.method + ")");
    }
    if (a.regularization &&
        !(*a.regularization >= kMinRegularization && *a.regularization <= kMaxRegularization)) {
      throw_usage_error("regularization = " + format_exact(*a.regularization) +
                        ": must be a number in [" + format_exact(kMinRegularization) + ", " +
                        format_exact(kMaxRegularization) + "] or 'optimal'");
    }
    r.regularization = a.regularization;
  }
  std::string error;
  if (!r.IsValid(&error)) throw_usage_error(design_field_names(error));
  return r;
}

void check_design_grid(int grid, const RestorationOptions& restoration) {
  if (grid == 0 || restoration.method == RestorationMethod::kInverse) return;
  throw_usage_error("grid = " + std::to_string(grid) +
                    ": the DFT grid is the inverse filter's (the simulator's M); restoration='" +
                    to_string(restoration.method) + "' uses the midpoint rule (grid=0)");
}

}  // namespace fss::python
