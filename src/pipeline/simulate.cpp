#include "fss/pipeline/simulate.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/memory_estimate.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/option_rules.h"
#include "pipeline/finite_checks.h"
#include "pipeline/fitted_restoration.h"
#include "pipeline/plan_core.h"
#include "pipeline/predict.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/run_checks.h"
#include "pipeline/trial_metrics.h"
#include "pipeline/velocity_prediction.h"
#include "pipeline/velocity_trials.h"

namespace fss {

namespace {

// Without noise every trial is the same run: run it once. False when an
// observed value is not finite.
bool run_noise_free(const RowPipeline& pipeline, const SimulationOptions& options,
                    const Image& input, SimulationReport& report, ObservedRowSink* observed,
                    ReadoutClipping& clipping) {
  const bool observed_finite =
      pipeline.restore_all(std::nullopt, report.restored, observed, &clipping);
  report.metrics = measure(report, input, report.restored);
  report.trials = {options.trials,
                   report.metrics.rmse,
                   0.0,
                   report.metrics.rmse_ci,
                   0.0,
                   report.metrics.ssim,
                   std::nullopt,
                   std::nullopt,
                   std::nullopt};
  if (report.metrics.ssim) report.trials.ssim_sd = 0.0;
  report.trial_metrics.assign(static_cast<std::size_t>(options.trials), report.metrics);
  if (options.trial_callback) options.trial_callback(options.trials, options.trials);
  return observed_finite;
}

// Trial t has the noise of seed + t; the first one's images and metrics are
// the report's. The first trial also makes the noise-free pass (RMSE_0 and
// S(j), returned), sharing each row's transforms. `observed_finite` is set
// false when an observed value is not finite.
NoiseFreeRun run_trials(const RowPipeline& pipeline, const SimulationOptions& options,
                        const Image& input, SimulationReport& report, ObservedRowSink* observed,
                        bool& observed_finite) {
  const int n = options.trials;
  RowPipeline::FirstTrial first = pipeline.first_trial(options.seed, report.rmse_first,
                                                       report.rmse_end, report.restored, observed);
  observed_finite = first.observed_finite;
  report.metrics = measure(report, input, report.restored);
  report.trial_metrics.push_back(report.metrics);
  TrialSums sums;
  sums.add(report.metrics);
  if (options.trial_callback) options.trial_callback(1, n);
  Image later_trial;  // restoration of the trials after the first, when there are any
  if (n > 1) later_trial = Image(report.restored.width, input.height, input.channels);
  for (int t = 1; t < n; ++t) {
    const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(t);
    observed_finite = pipeline.restore_all(seed, later_trial, nullptr) && observed_finite;
    const Metrics m = measure(report, input, later_trial);
    report.trial_metrics.push_back(m);
    sums.add(m);
    if (options.trial_callback) options.trial_callback(t + 1, n);
  }
  report.trials = sums.statistics(n);
  return std::move(first.noise_free);
}

// A full well or an ADC that clips readouts (docs/method.md §10): the
// simulation says so, and that the prediction is approximate.
void add_clipping_warnings(const NoiseFreeRun& run, SimulationReport& report) {
  const auto total = [&]() {
    const std::size_t readouts_per_pixel =
        report.options.mode == ShutterMode::kAnalog
            ? 1
            : static_cast<std::size_t>(std::count_if(report.gains.begin(), report.gains.end(),
                                                     [](double g) { return g != 0.0; }));
    return std::to_string(
        readouts_per_pixel * static_cast<std::size_t>(report.geometry.observed_width) *
        static_cast<std::size_t>(report.height) * static_cast<std::size_t>(report.channels));
  };
  if (run.saturated_readouts > 0) {
    report.warnings.push_back(
        std::to_string(run.saturated_readouts) + " of " + total() +
        " readouts saturate (mean charge at or above the full well or the ADC's top, "
        "docs/method.md §10): the observation is clipped and the predicted RMSE is approximate");
  }
  if (run.near_zero_readouts > 0) {
    report.warnings.push_back(
        std::to_string(run.near_zero_readouts) + " of " + total() +
        " readouts lie within 3 standard deviations of 0, where the ADC clips negative "
        "readouts (docs/method.md §10): the predicted RMSE is approximate");
  }
}

}  // namespace

namespace {

// Refuses, before anything is allocated, a run over options.max_memory_bytes.
void check_memory(const SimulationOptions& options, const Image& input, const ShutterCode& code,
                  const ObservedRowSink* observed_sink) {
  check_run_memory(
      {input.width, input.height, input.channels}, options, code, observed_sink != nullptr, 0,
      "a run on this " + std::to_string(input.width) + " x " + std::to_string(input.height) +
          " x " + std::to_string(input.channels) + " image");
}

// The report's fields the plan gives: geometry, windows, kernel, warnings.
SimulationReport planned_report(const PlanCore& plan, const SimulationOptions& options,
                                const Image& input, const ShutterCode& code) {
  SimulationReport report;
  report.options = options;
  report.options.trial_callback = nullptr;
  report.code_name = code.name;
  report.gains = code.gains;
  report.width = input.width;
  report.height = input.height;
  report.channels = input.channels;
  report.geometry = plan.geometry();
  report.rmse_first = plan.windows().rmse_first;
  report.rmse_end = plan.windows().rmse_end;
  report.rmse_ci_first = plan.windows().ci_first;
  report.rmse_ci_end = plan.windows().ci_end;
  report.kernel = plan.kernel();
  report.observed_divisor = plan.observed_divisor();
  report.warnings = plan.warnings();
  const int b = report.geometry.blur_length;
  if (options.rmse_margin_columns == kRmseMarginAuto && report.rmse_first < 3 * b) {
    report.warnings.push_back("RMSE margin auto: " + std::to_string(report.rmse_first) +
                              " columns, below the paper's 3B = " + std::to_string(3 * b) +
                              " (the image is narrower than 9B + 1 = " + std::to_string(9 * b + 1) +
                              ")");
  }
  return report;
}

// Allocates report.restored and, without a caller's sink, report.observed (Wo x H x C); returns
// the sink the first trial's observed rows go to: the caller's, or `kept` (report.observed's).
ObservedRowSink* allocate_outputs(const Image& input, ObservedRowSink* observed_sink,
                                  ImageRowSink& kept, SimulationReport& report) {
  const int wo = report.geometry.output_width;
  if (observed_sink == nullptr) {
    report.observed = Image(wo, input.height, input.channels);
    observed_sink = &kept;
  }
  report.restored = Image(wo, input.height, input.channels);
  return observed_sink;
}

// A run under a velocity distribution (docs/method.md §13): each trial at its own velocity on
// the plan's geometry, and the expected error averaged over the distribution.
SimulationReport run_over_velocities(const PlanCore& plan, const SimulationOptions& options,
                                     const Image& input, const ShutterCode& code,
                                     ObservedRowSink* observed_sink, SimulationReport report) {
  ImageRowSink kept_observed(report.observed);
  observed_sink = allocate_outputs(input, observed_sink, kept_observed, report);
  const bool observed_finite =
      run_velocity_trials(plan, options, input, code, report, observed_sink);
  check_finite(report, code, observed_finite);
  add_ssim_warning(report);
  report.prediction = predict_over_velocities(plan, report, input, code,
                                              kVelocityQuadratureTolerance, &report.warnings);
  check_prediction_finite(report, code);
  return report;
}

// The run once the inputs are checked and the memory guard passed.
SimulationReport run_planned(const PlanCore& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code,
                             ObservedRowSink* observed_sink) {
  SimulationReport report = planned_report(plan, options, input, code);
  if (options.velocity_distribution) {
    return run_over_velocities(plan, options, input, code, observed_sink, std::move(report));
  }

  // The filter: the plan's, or fitted to this image (docs/method.md §12).
  std::optional<FittedFilter> fitted;
  const RowRestorer* restorer = plan.restorer();
  report.restoration = plan.restoration();
  if (restorer == nullptr) {
    fitted.emplace(fit_restoration(plan, options, input, code));
    restorer = &*fitted->restorer;
    report.restoration = fitted->summary;
  }

  // Row pipeline: observe -> noise -> restore, row by row.
  const RowPipeline pipeline(input, plan.observer(), *restorer, options, report.geometry,
                             report.observed_divisor);
  if (pipeline.zero_bins() > 0) {
    report.zero_bins = pipeline.zero_bins();
    report.warnings.push_back(
        std::to_string(report.zero_bins) + " of the " +
        std::to_string(report.geometry.mirror_width / 2 + 1) +
        " frequencies of the deconvolution grid have K = 0 (|K| <= " +
        format_number(kZeroTolerance) +
        " dt sum |gain|): the restoration cannot recover them; it takes " +
        (options.restoration.method == RestorationMethod::kInverse ? "1 / K" : "its filter") +
        " as 0 there, so the restored image has nothing at those "
        "frequencies");
  }
  ImageRowSink kept_observed(report.observed);
  observed_sink = allocate_outputs(input, observed_sink, kept_observed, report);

  // Metrics of the first trial and over all trials; RMSE_0 and, with noise,
  // the observation noise's variance sums S(j).
  NoiseFreeRun noise_free;
  bool observed_finite = true;
  if (options.noise == NoiseModel::kNone) {
    ReadoutClipping clipping;
    observed_finite = run_noise_free(pipeline, options, input, report, observed_sink, clipping);
    noise_free.rmse = report.metrics.rmse;
    noise_free.saturated_readouts = clipping.saturated;
    noise_free.near_zero_readouts = clipping.near_zero;
  } else {
    noise_free = run_trials(pipeline, options, input, report, observed_sink, observed_finite);
  }
  check_finite(report, code, observed_finite);
  add_ssim_warning(report);

  // Prediction (docs/method.md §6, §6b): E[MSE] = RMSE_0^2 + sum_j W(j) S(j) / count,
  // and the stationary approximation RMSE_0^2 + m Q (100 / snr^2) M.
  report.prediction =
      fitted ? predict(report, input, noise_free, fitted->m_amplification, fitted->noise_weights)
             : predict(report, input, noise_free, plan.m_amplification(), plan.noise_weights());
  check_prediction_finite(report, code);
  add_clipping_warnings(noise_free, report);
  return report;
}

}  // namespace

SimulationReport Simulate(const SimulationOptions& options, const Image& input,
                          const ShutterCode& code, ObservedRowSink* observed_sink) {
  check_inputs(options, input, code);
  // Geometry and metric windows (docs/method.md §4, §5) and the memory
  // guard before anything is allocated; then the plan: kernel and warnings.
  check_memory(options, input, code, observed_sink);
  const PlanCore plan(options, input.width, code);
  return run_planned(plan, options, input, code, observed_sink);
}

SimulationReport Simulate(const SimulationPlan& plan, const SimulationOptions& options,
                          const Image& input, const ShutterCode& code,
                          ObservedRowSink* observed_sink) {
  check_inputs(options, input, code);
  if (!plan.fits(options, input.width, code)) {
    throw_usage_error("the simulation plan of code '" + escape_control_characters(code.name) +
                      "' was made for another code, mode, velocity, dt, RMSE margin, noise or "
                      "image width than this run");
  }
  check_memory(options, input, code, observed_sink);
  return run_planned(plan.core(), options, input, code, observed_sink);
}

SimulationPlan::SimulationPlan(const SimulationOptions& options, int width, const ShutterCode& code)
    : core_(std::make_shared<const PlanCore>(options, width, code)) {}

bool SimulationPlan::fits(const SimulationOptions& options, int width,
                          const ShutterCode& code) const {
  return core_->fits(options, width, code);
}

const Geometry& SimulationPlan::geometry() const { return core_->geometry(); }
const KernelAnalysis& SimulationPlan::kernel() const { return core_->kernel(); }
const std::vector<std::string>& SimulationPlan::warnings() const { return core_->warnings(); }
std::size_t SimulationPlan::bytes() const { return core_->bytes(); }

}  // namespace fss
