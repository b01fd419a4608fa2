// The sensor beyond photon noise (docs/method.md §10): read noise, dark current, full well and
// an ADC, in electrons. Every part is off by default: a default SensorModel observes exactly
// what the paper's photon-noise model does.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>

#include "fss/model/code.h"

namespace fss {

// Upper bound of the read noise, the dark current and the ADC gain (the range of dt and snr), so
// that their squares and products with a code's exposure stay finite.
inline constexpr double kMaxSensorScale = 1e100;

struct SensorModel {
  double read_noise_electrons = 0.0;             // sigma_r, RMS per readout, in [0, 1e100]
  double dark_current_electrons_per_slot = 0.0;  // d, mean electrons per unit slot, in [0, 1e100]
  // Charge capacity of a pixel per readout; empty: no full well.
  std::optional<double> full_well_electrons;
  int adc_bits = 0;                           // 0: no ADC; otherwise in [1, 32]
  double adc_gain_electrons_per_count = 1.0;  // G, in (0, 1e100]; used only with an ADC

  // True when any part is on (the observation then differs from the photon-noise model's).
  bool enabled() const;
  // True when the observation is linear in the charge: no full well and no ADC.
  bool linear() const;

  // False, with a message naming the field, its value and the rule, when a
  // field is out of range ("read_noise_electrons = -1: must be finite and >= 0").
  bool IsValid(std::string* error) const;
};

// Exposure of one readout in unit slots: dt (numerical: one frame per slot) or
// code_length * dt (analog: the one exposure).
double readout_exposure_slots(std::size_t code_length, double dt, ShutterMode mode);

// Variance, in electrons^2, that one readout of `exposure_slots` adds beyond
// its photo-electrons: sigma_r^2 + d * exposure + (ADC: G^2 / 12).
double readout_variance_electrons2(const SensorModel& sensor, double exposure_slots);

// Variance, in gray levels^2, of the observation of a constant landscape at level 100 through
// `gains` (before division by K(0)), lambda2 = snr^2 / 100 (docs/method.md §10). With a default
// sensor it is 100 Q (100 / snr^2), Q = noise_gain (prediction.h).
double level100_observation_variance(std::span<const double> gains, double dt, ShutterMode mode,
                                     double snr, const SensorModel& sensor);

// One readout's sensor parameters in electrons: a SensorModel at a given exposure, the form the
// noise samplers use.
struct SensorReadout {
  double dark_electrons = 0.0;  // d * exposure: mean dark charge, subtracted after the readout
  double read_noise_electrons = 0.0;  // sigma_r
  // Largest charge kept before read noise: the full well (infinite without one).
  double full_well_electrons = std::numeric_limits<double>::infinity();
  double adc_gain_electrons_per_count = 0.0;  // G; 0: no ADC
  double adc_max_counts = 0.0;                // 2^b - 1

  bool adc() const { return adc_gain_electrons_per_count > 0.0; }
  // The largest mean charge the readout passes unclipped: min(F, (2^b - 1) G).
  double clip_electrons() const;
  // Whether a readout of mean charge `charge` saturates: charge >= clip_electrons()
  // (at the clip exactly, the readout's distribution is already cut there).
  bool saturates(double charge) const { return charge >= clip_electrons(); }
  // The readout of `charge` (electrons, dark charge included) with read noise draw r ~ N(0, 1),
  // minus the dark mean (docs/method.md §10): q = min(charge, F) + sigma_r r; with an ADC
  // q = min(round+(q / G), 2^b - 1) G (round+ is 0 for q <= 0); result q - d * exposure.
  double read(double charge, double r) const;
};

// The readout of `sensor` at `exposure_slots` (readout_exposure_slots).
SensorReadout sensor_readout(const SensorModel& sensor, double exposure_slots);

}  // namespace fss
