#include "fss/model/sensor.h"

#include <algorithm>
#include <cmath>

#include "core/scaled_math.h"
#include "fss/core/error.h"
#include "model/noise.h"

namespace fss {

namespace {
// True when `value` is finite and >= 0.
bool nonnegative_finite(double value) { return std::isfinite(value) && value >= 0.0; }

bool fail(std::string* error, const std::string& field, double value, const std::string& rule) {
  if (error != nullptr) *error = field + " = " + format_exact(value) + ": " + rule;
  return false;
}
}  // namespace

bool SensorModel::enabled() const {
  return read_noise_electrons != 0.0 || dark_current_electrons_per_slot != 0.0 ||
         full_well_electrons.has_value() || adc_bits != 0;
}

bool SensorModel::linear() const { return !full_well_electrons.has_value() && adc_bits == 0; }

bool SensorModel::IsValid(std::string* error) const {
  if (!nonnegative_finite(read_noise_electrons)) {
    return fail(error, "read_noise_electrons", read_noise_electrons, "must be finite and >= 0");
  }
  if (read_noise_electrons > kMaxSensorScale) {
    return fail(error, "read_noise_electrons", read_noise_electrons, "must lie in [0, 1e100]");
  }
  if (!nonnegative_finite(dark_current_electrons_per_slot)) {
    return fail(error, "dark_current_electrons_per_slot", dark_current_electrons_per_slot,
                "must be finite and >= 0");
  }
  if (dark_current_electrons_per_slot > kMaxSensorScale) {
    return fail(error, "dark_current_electrons_per_slot", dark_current_electrons_per_slot,
                "must lie in [0, 1e100]");
  }
  if (full_well_electrons && !(std::isfinite(*full_well_electrons) && *full_well_electrons > 0.0)) {
    return fail(error, "full_well_electrons", *full_well_electrons, "must be finite and > 0");
  }
  if (adc_bits < 0 || adc_bits > 32) {
    return fail(error, "adc_bits", adc_bits, "must lie in [1, 32] (or 0 for no ADC)");
  }
  if (!(std::isfinite(adc_gain_electrons_per_count) && adc_gain_electrons_per_count > 0.0)) {
    return fail(error, "adc_gain_electrons_per_count", adc_gain_electrons_per_count,
                "must be finite and > 0");
  }
  if (adc_gain_electrons_per_count > kMaxSensorScale) {
    return fail(error, "adc_gain_electrons_per_count", adc_gain_electrons_per_count,
                "must lie in (0, 1e100]");
  }
  return true;
}

double readout_exposure_slots(std::size_t code_length, double dt, ShutterMode mode) {
  return mode == ShutterMode::kAnalog ? static_cast<double>(code_length) * dt : dt;
}

double readout_variance_electrons2(const SensorModel& sensor, double exposure_slots) {
  const double read = sensor.read_noise_electrons * sensor.read_noise_electrons;
  const double dark = sensor.dark_current_electrons_per_slot * exposure_slots;
  const double gain = sensor.adc_gain_electrons_per_count;
  const double quantization = sensor.adc_bits != 0 ? gain * gain / 12.0 : 0.0;
  return read + dark + quantization;
}

// numerical: sum_k alpha_k^2 (100 dt lambda2 + v_r) / lambda2^2
// analog:    (100 dt sum_k alpha_k lambda2 + v_r) / lambda2^2
// with v_r = readout_variance_electrons2 of the mode's readout.
double level100_observation_variance(std::span<const double> gains, double dt, ShutterMode mode,
                                     double snr, const SensorModel& sensor) {
  const double lambda2 = snr * snr / 100.0;
  const double readout =
      readout_variance_electrons2(sensor, readout_exposure_slots(gains.size(), dt, mode));
  const bool analog = mode == ShutterMode::kAnalog;
  double electrons2 = 0.0;
  if (analog) {
    double sum = 0.0;
    for (const double alpha : gains) sum += alpha;
    electrons2 = 100.0 * dt * sum * lambda2 + readout;
  } else {
    for (const double alpha : gains) electrons2 += alpha * alpha * (100.0 * dt * lambda2 + readout);
  }
  const double lambda4 = lambda2 * lambda2;
  if (std::isfinite(electrons2) && detail::is_normal_positive(lambda4)) {
    return electrons2 / lambda4;
  }
  // Electrons or lambda2^2 out of the range of doubles (snr, dt or the gains
  // far from 1): the same in gray levels, term by term,
  //   numerical: sum_k alpha_k^2 (100 dt / lambda2 + v_r / lambda2 / lambda2)
  //   analog:    100 dt sum_k alpha_k / lambda2 + v_r / lambda2 / lambda2
  double sum = 0.0;
  for (const double alpha : gains) sum += analog ? alpha : alpha * alpha;
  const double photon = 100.0 * dt / lambda2;
  const double per_readout = detail::divide_by_square(readout, lambda2);
  return analog ? photon * sum + per_readout : sum * (photon + per_readout);
}

double SensorReadout::clip_electrons() const {
  const double top = adc() ? adc_max_counts * adc_gain_electrons_per_count
                           : std::numeric_limits<double>::infinity();
  return std::min(full_well_electrons, top);
}

double SensorReadout::read(double charge, double r) const {
  // q = min(charge, F) + sigma_r r; ADC: q = min(round+(q / G), 2^b - 1) G; minus d * exposure
  double q = std::min(charge, full_well_electrons) + read_noise_electrons * r;
  if (adc()) {
    q = std::min(round_nonnegative(q / adc_gain_electrons_per_count), adc_max_counts) *
        adc_gain_electrons_per_count;
  }
  return q - dark_electrons;
}

SensorReadout sensor_readout(const SensorModel& sensor, double exposure_slots) {
  SensorReadout readout;
  readout.dark_electrons = sensor.dark_current_electrons_per_slot * exposure_slots;
  readout.read_noise_electrons = sensor.read_noise_electrons;
  if (sensor.full_well_electrons) readout.full_well_electrons = *sensor.full_well_electrons;
  if (sensor.adc_bits != 0) {
    readout.adc_gain_electrons_per_count = sensor.adc_gain_electrons_per_count;
    readout.adc_max_counts = std::ldexp(1.0, sensor.adc_bits) - 1.0;
  }
  return readout;
}

}  // namespace fss
