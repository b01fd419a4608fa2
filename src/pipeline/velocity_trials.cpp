#include "pipeline/velocity_trials.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/model/velocity_distribution.h"
#include "pipeline/plan_core.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/trial_metrics.h"

namespace fss {

SimulationOptions options_at_velocity(const SimulationOptions& options, double velocity) {
  SimulationOptions o = options;
  o.velocity_px_per_slot = velocity;
  o.velocity_distribution.reset();
  o.trials = 1;
  o.trial_callback = nullptr;
  return o;
}

double first_trial_velocity(const SimulationOptions& options) {
  return options.velocity_distribution
             ? trial_velocity(*options.velocity_distribution, options.seed, 0)
             : options.velocity_px_per_slot;
}

namespace {

// What one trial's restoration inverted.
struct TrialKernel {
  KernelAnalysis kernel;
  int zero_bins = 0;
  bool observed_finite = true;
};

// Observes `input` at `velocity` with the noise of `seed` (none: the expectation) and restores
// it into `restored` with the kernel part of that velocity on the plan's geometry.
TrialKernel run_trial(const PlanCore& plan, const SimulationOptions& options, const Image& input,
                      const ShutterCode& code, double velocity, std::optional<std::uint64_t> seed,
                      Image& restored, ObservedRowSink* observed) {
  const SimulationOptions o = options_at_velocity(options, velocity);
  const PlanCore core(o, plan.geometry(), code, PlanCore::VelocityPart::kTrial);
  const RowPipeline pipeline(input, core.observer(), *core.restorer(), o, plan.geometry(),
                             plan.observed_divisor());
  TrialKernel trial{core.kernel(), pipeline.zero_bins(), true};
  trial.observed_finite = pipeline.restore_all(seed, restored, observed);
  return trial;
}

// Trials of one kind (a kernel that is not invertible, zero bins): how many, and the range of
// their velocities.
struct TrialTally {
  int count = 0;
  double low = 0.0;
  double high = 0.0;

  void add(double velocity) {
    low = count == 0 ? velocity : std::min(low, velocity);
    high = count == 0 ? velocity : std::max(high, velocity);
    ++count;
  }
  // "N of the T trials (velocities a to b)"
  std::string text(int trials) const {
    return std::to_string(count) + " of the " + std::to_string(trials) + " trials" +
           (low == high
                ? " (velocity " + format_number(low) + ")"
                : " (velocities " + format_number(low) + " to " + format_number(high) + ")");
  }
};

void add_kernel_warnings(const TrialTally& not_invertible, const TrialTally& zero_bins,
                         const SimulationOptions& options, const ShutterCode& code,
                         SimulationReport& report) {
  const bool inverse = options.restoration.method == RestorationMethod::kInverse;
  if (not_invertible.count > 0) {
    const std::string at =
        options.restore_velocity_px_per_slot
            ? "the restore velocity " + format_exact(*options.restore_velocity_px_per_slot) + " of "
            : "the velocity of ";
    report.warnings.push_back(
        "code '" + escape_control_characters(code.name) + "' is not invertible at " + at +
        not_invertible.text(options.trials) +
        (inverse ? ": their restorations cannot recover the frequencies where K vanishes and "
                   "amplify the noise near them"
                 : ": the " + to_string(options.restoration.method) +
                       " restoration damps the frequencies where K vanishes"));
  }
  if (zero_bins.count > 0) {
    report.warnings.push_back(
        zero_bins.text(options.trials) +
        " have frequencies of the deconvolution grid where K = 0 (|K| <= " +
        format_number(kZeroTolerance) + " dt sum |gain|): their restorations take " +
        (inverse ? "1 / K" : "the filter") +
        " as 0 there, so the restored images have nothing at those frequencies");
  }
}

// The mean and sample standard deviation of the trials' MSE (RMSE^2), in two passes.
void set_mse_statistics(SimulationReport& report) {
  const auto n = static_cast<double>(report.trial_metrics.size());
  double sum = 0.0;
  for (const Metrics& m : report.trial_metrics) sum += m.rmse * m.rmse;
  const double mean = sum / n;
  double squares = 0.0;
  for (const Metrics& m : report.trial_metrics) {
    squares += (m.rmse * m.rmse - mean) * (m.rmse * m.rmse - mean);
  }
  report.trials.mse_mean = mean;
  report.trials.mse_sd = n > 1.0 ? std::sqrt(squares / (n - 1.0)) : 0.0;
}

}  // namespace

bool run_velocity_trials(const PlanCore& plan, const SimulationOptions& options, const Image& input,
                         const ShutterCode& code, SimulationReport& report,
                         ObservedRowSink* observed_sink) {
  const VelocityDistribution& distribution = *options.velocity_distribution;
  const int n = options.trials;
  Image later_trial;  // restoration of the trials after the first, when there are any
  if (n > 1) later_trial = Image(report.restored.width, input.height, input.channels);
  TrialSums sums;
  TrialTally not_invertible;
  TrialTally zero_bins;
  bool observed_finite = true;
  for (int t = 0; t < n; ++t) {
    const auto index = static_cast<std::uint64_t>(t);
    const double velocity = trial_velocity(distribution, options.seed, index);
    std::optional<std::uint64_t> seed;
    if (options.noise != NoiseModel::kNone) seed = options.seed + index;
    Image& restored = t == 0 ? report.restored : later_trial;
    const TrialKernel trial = run_trial(plan, options, input, code, velocity, seed, restored,
                                        t == 0 ? observed_sink : nullptr);
    observed_finite = observed_finite && trial.observed_finite;
    if (!trial.kernel.invertible) not_invertible.add(velocity);
    if (trial.zero_bins > 0) zero_bins.add(velocity);
    const Metrics m = measure(report, input, restored);
    if (t == 0) {
      report.kernel = trial.kernel;
      report.zero_bins = trial.zero_bins;
      report.metrics = m;
    }
    report.trial_metrics.push_back(m);
    report.trial_velocities.push_back(velocity);
    sums.add(m);
    if (options.trial_callback) options.trial_callback(t + 1, n);
  }
  report.trials = sums.statistics(n);
  set_mse_statistics(report);
  add_kernel_warnings(not_invertible, zero_bins, options, code, report);
  return observed_finite;
}

}  // namespace fss
