// The options of a simulation and the check of a code for a mode, which every interface
// validates before a run. Conventions: fss/fss.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "fss/model/code.h"
#include "fss/model/restoration.h"
#include "fss/model/sensor.h"
#include "fss/model/velocity_distribution.h"

namespace fss {

// Photon noise (docs/method.md §3): kPoisson draws every frame (the paper's sampler), kNone
// observes the expectation, kAggregated (numerical mode only, §6c) draws each pixel's
// normal-branch frames as one normal of the same mean and variance.
enum class NoiseModel { kPoisson, kNone, kAggregated };
std::string to_string(NoiseModel noise);
std::optional<NoiseModel> noise_model_from_string(std::string_view text);

// Receives the observed rows of the first trial, for a caller that stores them in its own form
// (fssim: 8-bit samples) instead of a Wo x H x C image of doubles. consume_row is called once per
// row with the Wo values SimulationReport::observed would hold, from the worker threads (the
// calling thread when there is only one), concurrently for different rows.
class ObservedRowSink {
 public:
  virtual ~ObservedRowSink() = default;
  virtual void consume_row(int channel, int row, std::span<const double> values) = 0;
};

struct SimulationOptions {
  ShutterMode mode = ShutterMode::kNumerical;
  double velocity_px_per_slot = 1.0;  // any real; the sign is the direction along rows
  // A distribution of velocities (docs/method.md §13): trial t observes at trial_velocity(
  // distribution, seed, t) instead of velocity_px_per_slot, which must then stay at its default 1
  // (IsValid); the geometry is that of the support's largest |v|, the same for every trial.
  std::optional<VelocityDistribution> velocity_distribution;
  // Velocity assumed by the restoration (to measure the cost of a wrong estimate); empty means
  // the true velocity. B covers both, so the true velocity given here is exactly a normal run.
  std::optional<double> restore_velocity_px_per_slot;
  double dt = 1.0;     // time slot length, in [kMinScale, kMaxScale]
  double snr = 100.0;  // in [kMinScale, kMaxScale]
  std::uint64_t seed = 0;
  NoiseModel noise = NoiseModel::kPoisson;
  // Read noise, dark current, full well and ADC (docs/method.md §10); all off by default (the
  // paper's photon noise).
  SensorModel sensor;
  // The restoration (docs/method.md §12); the default is the paper's inverse filter. A
  // simulation estimates a power-law prior's level itself: prior_level stays empty.
  RestorationOptions restoration;
  // Columns left out at each side of the output for the RMSE; -1 means 3 B.
  int rmse_margin_columns = -1;
  // Independent noise realizations, seeds seed, seed + 1, ...; the images and headline metrics
  // are the first's.
  int trials = 1;
  int threads = 0;  // 0: all hardware threads; never changes the results
  // Refuse, before allocating, a run whose estimated peak memory (memory_estimate.h) exceeds
  // this many bytes; 0 means no limit.
  std::size_t max_memory_bytes = 0;
  // Called after each trial with (done, total); may be empty. Not kept in the report.
  std::function<void(int, int)> trial_callback;

  // False, with a message naming the field, its value and the rule (option_rules.h), when an
  // option is out of range on its own (image and code checks are Simulate's).
  bool IsValid(std::string* error) const;
};

// Throws the usage fss::Error Simulate would for a code the mode cannot use: no gains, more than
// kMaxCodeLength, a non-finite gain, only zero gains, a largest |gain| outside [1e-100, 1e100], or
// (analog) a gain outside [0, 1]. The one check of a code, which every command applies.
void check_code_for_mode(const ShutterCode& code, ShutterMode mode);

}  // namespace fss
