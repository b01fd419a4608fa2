// The trials of a run under a velocity distribution (docs/method.md §13): each trial draws its
// velocity, observes and restores on the run's one geometry (that of the support's largest |v|),
// and is measured on the same pixels as every other. Internal to the library.
#pragma once

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss {

class PlanCore;

// The options of one velocity of a run under a distribution: `options` with
// velocity_px_per_slot = `velocity`, no distribution and one trial (so that the row pipeline
// records no aggregated-noise plan for trials that would observe at another velocity).
SimulationOptions options_at_velocity(const SimulationOptions& options, double velocity);

// Runs the trials of `options` (which has a velocity distribution) on `plan` (its PlanCore):
// trial t observes `input` at v_t = trial_velocity(distribution, seed, t) with the noise of
// seed + t (its expectation without noise) and restores with the kernel at v_t, or at the restore
// velocity when one is given, on the plan's geometry. The first trial's observed rows go to
// `observed_sink`, its restoration to report.restored (Wo x H x C, allocated by the caller); its
// metrics, kernel and zero bins are the report's. Sets report.trial_metrics,
// report.trial_velocities, report.trials (with mse_mean and mse_sd) and the warnings of the
// trials whose kernel is not invertible or has zero bins. False when an observed value is not
// finite.
bool run_velocity_trials(const PlanCore& plan, const SimulationOptions& options, const Image& input,
                         const ShutterCode& code, SimulationReport& report,
                         ObservedRowSink* observed_sink);

}  // namespace fss
