#include "fss/pipeline/option_rules.h"

#include <cmath>

namespace fss {

// The scale range [kMinScale, kMaxScale] is far enough from the limits of double precision that
// K, lambda2 = snr^2 / 100 and their products stay finite and nonzero. The integer rules take
// long long, so that a caller can pass a parsed value that does not fit an int and still get the
// rule it breaks.

std::string velocity_rule(double velocity) {
  return std::isfinite(velocity) ? std::string() : "must be a finite number";
}

bool scale_is_positive(double value) { return std::isfinite(value) && value > 0.0; }

std::string scale_rule(double value) {
  if (!scale_is_positive(value)) return "must be finite and > 0";
  if (!(value >= kMinScale && value <= kMaxScale)) return "must lie in [1e-100, 1e100]";
  return {};
}

std::string margin_rule(long long columns) {
  if (columns > kMaxMarginColumns) return "must be at most " + std::to_string(kMaxMarginColumns);
  if (columns < kRmseMarginAuto) return "must be >= 0 (or -1 for the default 3B, -2 for auto)";
  return {};
}

std::string noise_rule(bool aggregated, bool analog) {
  return aggregated && analog
             ? "must be poisson or none in analog mode (aggregated noise sums the frames of the "
               "numerical mode)"
             : std::string();
}

// The aggregated noise adds the read noise and the dark current exactly but cannot clip a frame
// it does not draw (docs/method.md §10).
std::string sensor_noise_rule(bool aggregated, bool sensor_linear) {
  return aggregated && !sensor_linear
             ? "must be poisson or none with a full well or an ADC (the aggregated noise does not "
               "draw each frame's charge)"
             : std::string();
}

std::string distribution_velocity_rule(double velocity) {
  return velocity == 1.0 ? std::string()
                         : "is the velocity of a run without a distribution: leave it at its "
                           "default 1 with a velocity distribution, from which each trial draws "
                           "its velocity";
}

std::string distribution_restoration_rule(bool fitted) {
  return fitted ? "cannot be used with a velocity distribution: its filter is fitted to the run "
                  "at one velocity; use the inverse filter, or tikhonov with a given "
                  "regularization"
                : std::string();
}

std::string trials_rule(long long trials) { return trials < 1 ? "must be >= 1" : std::string(); }

std::string threads_rule(long long threads) {
  return threads < 0 ? "must be >= 0 (0: all)" : std::string();
}

}  // namespace fss
