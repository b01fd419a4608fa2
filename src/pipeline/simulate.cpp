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
#include "pipeline/fitted_restoration.h"
#include "pipeline/plan_core.h"
#include "pipeline/predict.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/run_checks.h"
#include "pipeline/ssim.h"

namespace fss {

namespace {

// RMSE and RMSE_CI of one restoration over the report's windows
// (docs/method.md §5).
Metrics measure(const SimulationReport& report, const Image& input, const Image& restored) {
  const int offset = report.output_first_column();
  Metrics m;
  m.rmse = rmse(input, offset, restored, report.rmse_first, report.rmse_end);
  m.psnr = psnr(m.rmse);
  m.rmse_ci = rmse_contrast_invariant(input, offset, restored, report.rmse_ci_first,
                                      report.rmse_ci_end, report.options.threads);
  m.psnr_ci = psnr(m.rmse_ci);
  m.ssim = structural_similarity(input, offset, restored, report.rmse_first, report.rmse_end,
                                 report.options.threads);
  return m;
}

double sample_sd(double sum, double sum_sq, int n) {
  if (n < 2) return 0.0;
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)));
}

// Sums of the trials' metrics, for their means and sample deviations.
struct TrialSums {
  double rmse = 0.0, rmse_sq = 0.0, ci = 0.0, ci_sq = 0.0, ssim = 0.0, ssim_sq = 0.0;
  bool has_ssim = true;

  void add(const Metrics& m) {
    rmse += m.rmse;
    rmse_sq += m.rmse * m.rmse;
    ci += m.rmse_ci;
    ci_sq += m.rmse_ci * m.rmse_ci;
    has_ssim = has_ssim && m.ssim.has_value();
    if (m.ssim) ssim += *m.ssim, ssim_sq += *m.ssim * *m.ssim;
  }
  TrialStatistics statistics(int n) const {
    TrialStatistics t{n,
                      rmse / n,
                      sample_sd(rmse, rmse_sq, n),
                      ci / n,
                      sample_sd(ci, ci_sq, n),
                      std::nullopt,
                      std::nullopt};
    if (has_ssim) t.ssim_mean = ssim / n, t.ssim_sd = sample_sd(ssim, ssim_sq, n);
    return t;
  }
};

// Without noise every trial is the same run: run it once. False when an
// observed value is not finite.
bool run_noise_free(const RowPipeline& pipeline, const SimulationOptions& options,
                    const Image& input, SimulationReport& report, ObservedRowSink* observed,
                    ReadoutClipping& clipping) {
  const bool observed_finite =
      pipeline.restore_all(std::nullopt, report.restored, observed, &clipping);
  report.metrics = measure(report, input, report.restored);
  report.trials = {options.trials,      report.metrics.rmse, 0.0, report.metrics.rmse_ci, 0.0,
                   report.metrics.ssim, std::nullopt};
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

// "the gains of code 'c' (|gain| from a to b), dt x, snr y and read noise z
// e-": the settings whose scales multiply in a run's numbers (the sensor's
// parts that are on), for an error when they leave double precision.
std::string scale_settings(const SimulationOptions& options, const ShutterCode& code) {
  double smallest = 0.0;
  for (const double gain : code.gains) {
    if (gain != 0.0 && (smallest == 0.0 || std::abs(gain) < smallest)) smallest = std::abs(gain);
  }
  std::vector<std::string> parts = {
      "the gains of code '" + escape_control_characters(code.name) + "' (|gain| from " +
          format_exact(smallest) + " to " + format_exact(gain_max_abs(code.gains)) + ")",
      "dt " + format_exact(options.dt), "snr " + format_exact(options.snr)};
  const SensorModel& s = options.sensor;
  if (s.read_noise_electrons != 0.0) {
    parts.push_back("read noise " + format_exact(s.read_noise_electrons) + " e-");
  }
  if (s.dark_current_electrons_per_slot != 0.0) {
    parts.push_back("dark current " + format_exact(s.dark_current_electrons_per_slot) + " e-/slot");
  }
  if (s.full_well_electrons) {
    parts.push_back("full well " + format_exact(*s.full_well_electrons) + " e-");
  }
  if (s.adc_bits != 0) {
    parts.push_back("ADC gain " + format_exact(s.adc_gain_electrons_per_count) + " e-/count");
  }
  std::string text = parts.front();
  for (std::size_t i = 1; i < parts.size(); ++i) {
    text += (i + 1 == parts.size() ? " and " : ", ") + parts[i];
  }
  return text;
}

// Extreme gains (1e-320, 1e308), dt, snr or sensor can leave the range of
// doubles: an error, never a silent NaN.
void check_finite(const SimulationReport& report, const ShutterCode& code, bool observed_finite) {
  const auto finite = [](double value) { return std::isfinite(value); };
  const bool ssim_finite = finite(report.metrics.ssim.value_or(0.0)) &&
                           finite(report.trials.ssim_mean.value_or(0.0)) &&
                           finite(report.trials.ssim_sd.value_or(0.0));
  if (ssim_finite && finite(report.metrics.rmse) && finite(report.metrics.rmse_ci) &&
      finite(report.trials.rmse_mean) && finite(report.trials.rmse_sd) &&
      finite(report.trials.rmse_ci_mean) && finite(report.trials.rmse_ci_sd) && observed_finite &&
      std::all_of(report.restored.data.begin(), report.restored.data.end(), finite)) {
    return;
  }
  throw_usage_error("the simulation left the range of double-precision numbers (RMSE " +
                    format_exact(report.metrics.rmse) +
                    "): " + scale_settings(report.options, code) + " are too extreme together");
}

// The prediction of an invertible code is finite (docs/method.md §6): where
// its variance terms leave double precision although the simulation did not,
// an error naming the settings instead of an infinite or NaN figure.
void check_prediction_finite(const SimulationReport& report, const ShutterCode& code) {
  const Prediction& p = report.prediction;
  bool finite = std::isfinite(p.window_mean) && std::isfinite(p.q);
  if (p.finite) {
    for (const double value :
         {p.m_amplification, p.noise, p.rmse, p.sigma, p.rmse_stationary, p.snr_level100}) {
      finite = finite && std::isfinite(value);
    }
  }
  if (finite) return;
  throw_usage_error(
      "the error prediction left the range of double-precision numbers (predicted RMSE " +
      format_exact(p.rmse) + ", stationary " + format_exact(p.rmse_stationary) +
      ", SNR at level 100 " + format_exact(p.snr_level100) +
      "): " + scale_settings(report.options, code) + " are too extreme together");
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
  return report;
}

// The run once the inputs are checked and the memory guard passed.
SimulationReport run_planned(const PlanCore& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code,
                             ObservedRowSink* observed_sink) {
  SimulationReport report = planned_report(plan, options, input, code);

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
  const int wo = report.geometry.output_width;
  ImageRowSink kept_observed(report.observed);
  if (observed_sink == nullptr) {
    report.observed = Image(wo, input.height, input.channels);
    observed_sink = &kept_observed;
  }
  report.restored = Image(wo, input.height, input.channels);

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
  if (!report.metrics.ssim) {
    report.warnings.push_back(
        "SSIM is null: it is taken over the RMSE window, which must start at least 5 columns "
        "inside the output (a margin of 5 or more) on an image of at least 11 rows, so that each "
        "pixel's 11 x 11 window lies inside it (docs/method.md §5)");
  }

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
