// The rules of the simulation options, in one place: SimulationOptions::IsValid
// (simulate.h) and the fssim command line both check values with these
// functions instead of copies of the bounds.
//
// Each *_rule function returns "" when the value is fine, otherwise the rule it
// breaks as a phrase beginning with "must", written to follow the value:
//   IsValid:  "<field> = <value>: " + phrase   e.g. "dt = 1e-200: must lie in [1e-100, 1e100]"
//   fssim:    "--<option>: value <text> " + phrase   e.g. "--snr: value -1 must be finite and > 0"
// The integer rules take long long, so that a caller can pass a parsed value
// that does not fit an int and still get the rule it breaks.
#pragma once

#include <string>

namespace fss {

// Bounds of SimulationOptions::dt and ::snr, and of the RMSE margin. The scale
// range is far enough from the limits of double precision that K,
// lambda2 = snr^2 / 100 and their products stay finite and nonzero.
inline constexpr double kMinScale = 1e-100;
inline constexpr double kMaxScale = 1e100;
inline constexpr int kMaxMarginColumns = 1 << 16;

// velocity_px_per_slot, restore_velocity_px_per_slot: any finite number.
// "must be a finite number".
std::string velocity_rule(double velocity);

// dt, snr: finite and > 0 ("must be finite and > 0"), then within
// [kMinScale, kMaxScale] ("must lie in [1e-100, 1e100]"). scale_is_positive
// tells the two apart for a caller that words them differently.
std::string scale_rule(double value);
bool scale_is_positive(double value);  // finite and > 0, whatever the range

// rmse_margin_columns: -1 (the default 3B) or [0, kMaxMarginColumns].
// "must be at most 65536" or "must be >= 0 (or -1 for the default 3B)".
std::string margin_rule(long long columns);

// noise: the aggregated noise sums the frames of the numerical mode, so with
// the analog mode it "must be poisson or none in analog mode (aggregated
// noise sums the frames of the numerical mode)".
std::string noise_rule(bool aggregated, bool analog);

// noise with a sensor: the aggregated noise adds the read noise and the dark
// current exactly but cannot clip a frame it does not draw, so with a full
// well or an ADC it "must be poisson or none with a full well or an ADC (the
// aggregated noise does not draw each frame's charge)".
std::string sensor_noise_rule(bool aggregated, bool sensor_linear);

// trials: "must be >= 1".
std::string trials_rule(long long trials);

// threads (0: all hardware threads): "must be >= 0 (0: all)".
std::string threads_rule(long long threads);

}  // namespace fss
