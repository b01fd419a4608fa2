// The rules of the simulation options, shared by SimulationOptions::IsValid and the fssim command
// line. Each *_rule returns "" for a fine value, otherwise the rule it breaks as a phrase that
// follows the value: "dt = 1e-200: must lie in [1e-100, 1e100]".
#pragma once

#include <string>

namespace fss {

// Bounds of SimulationOptions::dt and ::snr, and of the RMSE margin.
inline constexpr double kMinScale = 1e-100;
inline constexpr double kMaxScale = 1e100;
inline constexpr int kMaxMarginColumns = 1 << 16;
// Special values of rmse_margin_columns: the paper's 3B, and auto (geometry.h, rmse_margin).
inline constexpr int kRmseMarginDefault = -1;
inline constexpr int kRmseMarginAuto = -2;

// velocity_px_per_slot, restore_velocity_px_per_slot: any finite number.
// "must be a finite number".
std::string velocity_rule(double velocity);

// dt, snr: finite and > 0 ("must be finite and > 0"), then within [kMinScale, kMaxScale] ("must
// lie in [1e-100, 1e100]"). scale_is_positive tells the two apart.
std::string scale_rule(double value);
bool scale_is_positive(double value);  // finite and > 0, whatever the range

// rmse_margin_columns: kRmseMarginDefault (3B), kRmseMarginAuto or [0, kMaxMarginColumns].
// "must be at most 65536" or "must be >= 0 (or -1 for the default 3B, -2 for auto)".
std::string margin_rule(long long columns);

// noise: not aggregated in analog mode ("must be poisson or none in analog mode ...").
std::string noise_rule(bool aggregated, bool analog);

// noise with a sensor: not aggregated with a full well or an ADC ("must be poisson or none with
// a full well or an ADC ...").
std::string sensor_noise_rule(bool aggregated, bool sensor_linear);

// velocity_px_per_slot under a velocity distribution (docs/method.md §13): its default 1, since
// each trial draws its own velocity. "is the velocity of a run without a distribution: ...".
std::string distribution_velocity_rule(double velocity);

// The restoration under a velocity distribution: a filter that does not depend on the run
// (the inverse filter, Tikhonov at a given lambda); `fitted` is a filter fitted to the run at one
// velocity (Tikhonov's optimal lambda, Wiener). "cannot be used with a velocity distribution: ...".
std::string distribution_restoration_rule(bool fitted);

// trials: "must be >= 1".
std::string trials_rule(long long trials);

// threads (0: all hardware threads): "must be >= 0 (0: all)".
std::string threads_rule(long long threads);

}  // namespace fss
