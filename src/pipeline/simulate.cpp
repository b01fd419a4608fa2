#include "fss/pipeline/simulate.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/noise_weights.h"
#include "pipeline/row_pipeline.h"

namespace fss {

namespace {
constexpr detail::EnumNames<NoiseModel, 3> kNoiseModelNames{
    {{NoiseModel::kPoisson, "poisson"},
     {NoiseModel::kNone, "none"},
     {NoiseModel::kAggregated, "aggregated"}}};
}  // namespace

std::string to_string(NoiseModel noise) { return detail::enum_name(kNoiseModelNames, noise); }

std::optional<NoiseModel> noise_model_from_string(std::string_view text) {
  return detail::enum_from_name(kNoiseModelNames, text);
}

bool SimulationOptions::IsValid(std::string* error) const {
  // True, with the message, when `rule` (option_rules.h) is broken.
  const auto broken = [&](const char* field, const std::string& value, const std::string& rule) {
    if (rule.empty()) return false;
    if (error) *error = std::string(field) + " = " + value + ": " + rule;
    return true;
  };
  if (broken("velocity_px_per_slot", format_exact(velocity_px_per_slot),
             velocity_rule(velocity_px_per_slot))) {
    return false;
  }
  if (restore_velocity_px_per_slot &&
      broken("restore_velocity_px_per_slot", format_exact(*restore_velocity_px_per_slot),
             velocity_rule(*restore_velocity_px_per_slot))) {
    return false;
  }
  // The sign of either scale is reported before the range of either.
  for (const bool positive : {false, true}) {
    if (scale_is_positive(dt) == positive && broken("dt", format_exact(dt), scale_rule(dt))) {
      return false;
    }
    if (scale_is_positive(snr) == positive && broken("snr", format_exact(snr), scale_rule(snr))) {
      return false;
    }
  }
  std::string sensor_error;
  if (!sensor.IsValid(&sensor_error)) {
    if (error) *error = "sensor." + sensor_error;
    return false;
  }
  const std::string margin = std::to_string(rmse_margin_columns);
  return !(broken("noise", to_string(noise),
                  noise_rule(noise == NoiseModel::kAggregated, mode == ShutterMode::kAnalog)) ||
           broken("noise", to_string(noise),
                  sensor_noise_rule(noise == NoiseModel::kAggregated, sensor.linear())) ||
           broken("rmse_margin_columns", margin, margin_rule(rmse_margin_columns)) ||
           broken("trials", std::to_string(trials), trials_rule(trials)) ||
           broken("threads", std::to_string(threads), threads_rule(threads)));
}

void check_code_for_mode(const ShutterCode& code, ShutterMode mode) {
  if (code.gains.empty())
    throw_usage_error("code '" + escape_control_characters(code.name) + "' has no gains");
  if (code.gains.size() > static_cast<std::size_t>(kMaxCodeLength)) {
    throw_usage_error("code '" + escape_control_characters(code.name) + "' has " +
                      std::to_string(code.gains.size()) + " gains, more than " +
                      std::to_string(kMaxCodeLength) + " (the longest code fssim analyses)");
  }
  for (std::size_t k = 0; k < code.gains.size(); ++k) {
    if (!std::isfinite(code.gains[k])) {
      throw_usage_error("code '" + escape_control_characters(code.name) + "': gain " +
                        std::to_string(k) + " is " + format_exact(code.gains[k]) +
                        ", gains must be finite");
    }
  }
  const double largest = gain_max_abs(code.gains);
  if (largest == 0.0) {
    throw_usage_error("code '" + escape_control_characters(code.name) +
                      "' has only zero gains: its transfer function is 0 and nothing is observed");
  }
  // sup |alpha| in [1e-100, 1e100] (L <= 1024): sum alpha, sum alpha^2 and
  // |K| stay finite and nonzero, as dt and snr do within the same range.
  if (const std::string rule = scale_rule(largest); !rule.empty()) {
    throw_usage_error("code '" + escape_control_characters(code.name) + "': its largest |gain| " +
                      format_exact(largest) + " is out of range: it " + rule +
                      " (scale the gains)");
  }
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < code.gains.size(); ++k) {
      const double g = code.gains[k];
      if (!(g >= 0.0 && g <= 1.0)) {
        throw_usage_error("code '" + escape_control_characters(code.name) +
                          "' cannot be used in analog mode: gain " + std::to_string(k) + " is " +
                          format_exact(g) +
                          ", analog gains must lie in [0, 1] (use --mode numerical)");
      }
    }
  }
}

namespace {

// The dark charge of one readout, D = d * exposure, is drawn in double
// precision and subtracted again: its Poisson noise sqrt(D) is resolved in
// steps of ulp(D) ~ 2^-52 D, 2^-12 sqrt(D) at D = 1e24, and above about
// 2^104 ~ 2e31 it and the photo-electrons vanish in round-off (the
// observation comes out as 0). Refused above 1e24 e-.
constexpr double kMaxDarkChargeElectrons = 1e24;

void check_dark_charge(const SimulationOptions& options, const ShutterCode& code) {
  const double exposure = readout_exposure_slots(code.gains.size(), options.dt, options.mode);
  const double charge = options.sensor.dark_current_electrons_per_slot * exposure;
  if (charge <= kMaxDarkChargeElectrons) return;
  throw_usage_error("dark current " + format_exact(options.sensor.dark_current_electrons_per_slot) +
                    " e-/slot over a readout's exposure of " + format_exact(exposure) +
                    " (dt; L dt in analog mode) is a dark charge of " + format_exact(charge) +
                    " e-, more than the " + format_number(kMaxDarkChargeElectrons) +
                    " e- whose Poisson noise double precision can resolve: lower the dark "
                    "current or dt");
}

void check_inputs(const SimulationOptions& options, const Image& input, const ShutterCode& code) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  check_code_for_mode(code, options.mode);
  check_dark_charge(options, code);
  if (input.channels != 1 && input.channels != 3) {
    throw_usage_error("input has " + std::to_string(input.channels) +
                      " channels, expected 1 (gray) or 3 (RGB)");
  }
}

// Refuses, before anything is allocated, a run over options.max_memory_bytes.
void check_memory(const SimulationOptions& options, const Image& input, const Geometry& g,
                  int code_length, const ObservedRowSink* observed_sink) {
  if (options.max_memory_bytes == 0) return;
  const std::size_t needed = estimate_working_memory_bytes(
      input.width, input.height, input.channels, g, options, code_length, observed_sink);
  if (needed > options.max_memory_bytes) {
    throw_memory_limit_error("a run on this " + std::to_string(input.width) + " x " +
                                 std::to_string(input.height) + " x " +
                                 std::to_string(input.channels) + " image",
                             needed, options.max_memory_bytes);
  }
}

// The geometry of a run (docs/method.md §4): the blur length B covers both
// velocities. Throws a usage fss::Error for an image too narrow.
Geometry run_geometry(const SimulationOptions& options, int width, const ShutterCode& code) {
  const double v = options.velocity_px_per_slot;
  const double v_r = options.restore_velocity_px_per_slot.value_or(v);
  if (std::abs(v_r) > std::abs(v)) {
    // The blur length is the restore velocity's: a blur wider than the
    // image is said to be its own (Geometry::compute would name "velocity").
    const double motion = std::ceil(std::abs(v_r) * options.dt * code.length());
    if (!(motion < static_cast<double>(width))) {
      throw_usage_error(
          "the blur of restore velocity " + format_exact(v_r) + " (--restore-velocity) over " +
          std::to_string(code.length()) + " slots of dt " + format_exact(options.dt) + " spans " +
          format_exact(motion) + " pixels, more than the image width " + std::to_string(width));
    }
    return Geometry::compute(width, code.length(), v_r, options.dt);
  }
  return Geometry::compute(width, code.length(), v, options.dt);
}

// The geometry of a plan, after the checks Simulate makes first.
Geometry checked_geometry(const SimulationOptions& options, int width, const ShutterCode& code) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  check_code_for_mode(code, options.mode);
  check_dark_charge(options, code);
  return run_geometry(options, width, code);
}

}  // namespace

SimulationPlan::SimulationPlan(const SimulationOptions& options, int width, const ShutterCode& code)
    : code_name_(code.name),
      gains_(code.gains),
      mode_(options.mode),
      velocity_(options.velocity_px_per_slot),
      restore_velocity_(options.restore_velocity_px_per_slot.value_or(velocity_)),
      dt_(options.dt),
      margin_(options.rmse_margin_columns),
      noisy_(options.noise != NoiseModel::kNone),
      geometry_(checked_geometry(options, width, code)),
      windows_(metric_windows(geometry_, margin_)),
      observer_(width, code.gains, options.mode, observation_params(options, geometry_)),
      restorer_(geometry_, code.gains, restore_velocity_, dt_) {
  // The kernel the restoration inverts, K at the restore velocity v_r
  // (docs/method.md §1), the divisor of the observed image, and their warnings.
  kernel_ = analyze_kernel(code.gains, restore_velocity_, dt_);
  if (!kernel_.invertible) {
    warnings_.push_back("code '" + escape_control_characters(code.name) +
                        "' is not invertible at velocity " + format_exact(restore_velocity_) +
                        ": min |K| = " + format_number(kernel_.min_abs) +
                        " at xi = " + format_number(kernel_.min_abs_xi) +
                        "; the restoration cannot recover the frequencies where K vanishes and "
                        "amplifies the noise near them: no finite error prediction exists");
  }
  observed_divisor_ = kernel_.k0;
  if (transfer_vanishes(std::abs(kernel_.k0), transfer_scale(code.gains, dt_))) {
    observed_divisor_ = dt_ * gain_max_abs(code.gains);
    warnings_.push_back("K(0) = dt * sum of gains vanishes (it is " + format_number(kernel_.k0) +
                        "): observed.png is divided by dt * max |gain| = " +
                        format_number(observed_divisor_) + " instead");
  }
  // The prediction's M and W(j) (docs/method.md §6, §6b).
  m_amplification_ = std::numeric_limits<double>::infinity();
  if (kernel_.invertible) {
    m_amplification_ =
        mean_inverse_power(code.gains, restore_velocity_, dt_, geometry_.mirror_width);
    if (noisy_) {
      noise_weights_ = noise_energy_weights(geometry_, code.gains, restore_velocity_, dt_,
                                            windows_.rmse_first, windows_.rmse_end);
    }
  }
}

bool SimulationPlan::fits(const SimulationOptions& options, int width,
                          const ShutterCode& code) const {
  const double v = options.velocity_px_per_slot;
  // Compared as bits: -0.0 and 0.0 are different velocities to the filters.
  const auto same = [](double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
  };
  return code.name == code_name_ && code.gains.size() == gains_.size() &&
         std::equal(gains_.begin(), gains_.end(), code.gains.begin(), same) &&
         options.mode == mode_ && same(v, velocity_) &&
         same(options.restore_velocity_px_per_slot.value_or(v), restore_velocity_) &&
         same(options.dt, dt_) && width == geometry_.width &&
         options.rmse_margin_columns == margin_ &&
         (options.noise == NoiseModel::kNone || noisy_ || !kernel_.invertible);
}

std::size_t SimulationPlan::bytes() const {
  const std::size_t bins = static_cast<std::size_t>(geometry_.width) / 2 + 1;
  const std::size_t filters = (mode_ == ShutterMode::kAnalog ? 1 : gains_.size()) * bins;
  return sizeof(*this) + sizeof(std::complex<double>) * filters + restorer_.bytes() +
         sizeof(double) * (noise_weights_.size() + gains_.size());
}

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
  return m;
}

double sample_sd(double sum, double sum_sq, int n) {
  if (n < 2) return 0.0;
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)));
}

// Sums of the trials' metrics, for their means and sample deviations.
struct TrialSums {
  double rmse = 0.0, rmse_sq = 0.0, ci = 0.0, ci_sq = 0.0;

  void add(const Metrics& m) {
    rmse += m.rmse;
    rmse_sq += m.rmse * m.rmse;
    ci += m.rmse_ci;
    ci_sq += m.rmse_ci * m.rmse_ci;
  }
  TrialStatistics statistics(int n) const {
    return {n, rmse / n, sample_sd(rmse, rmse_sq, n), ci / n, sample_sd(ci, ci_sq, n)};
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
  report.trials = {options.trials, report.metrics.rmse, 0.0, report.metrics.rmse_ci, 0.0};
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
  if (finite(report.metrics.rmse) && finite(report.metrics.rmse_ci) &&
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

// The report's fields the plan gives: geometry, windows, kernel, warnings.
SimulationReport planned_report(const SimulationPlan& plan, const SimulationOptions& options,
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
SimulationReport run_planned(const SimulationPlan& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code,
                             ObservedRowSink* observed_sink) {
  SimulationReport report = planned_report(plan, options, input, code);

  // Row pipeline: observe -> noise -> restore, row by row.
  const RowPipeline pipeline(input, plan.observer(), plan.restorer(), options, report.geometry,
                             report.observed_divisor);
  if (pipeline.zero_bins() > 0) {
    report.zero_bins = pipeline.zero_bins();
    report.warnings.push_back(
        std::to_string(report.zero_bins) + " of the " +
        std::to_string(report.geometry.mirror_width / 2 + 1) +
        " frequencies of the deconvolution grid have K = 0 (|K| <= " +
        format_number(kZeroTolerance) +
        " dt sum |gain|): the restoration cannot recover them; it takes 1 / K as 0 there, so "
        "the restored image has nothing at those frequencies");
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

  // Prediction (docs/method.md §6, §6b): E[MSE] = RMSE_0^2 + sum_j W(j) S(j) / count,
  // and the stationary approximation RMSE_0^2 + m Q (100 / snr^2) M.
  report.prediction = predict(report, input, noise_free, plan);
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
  const Geometry geometry = run_geometry(options, input.width, code);
  metric_windows(geometry, options.rmse_margin_columns);
  check_memory(options, input, geometry, code.length(), observed_sink);
  const SimulationPlan plan(options, input.width, code);
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
  check_memory(options, input, plan.geometry(), code.length(), observed_sink);
  return run_planned(plan, options, input, code, observed_sink);
}

std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry, int trials,
                                          const ObservedRowSink* observed_sink,
                                          std::size_t extra_encoding_bytes_per_sample) {
  const bool keep_observed = observed_sink == nullptr;
  const auto w = static_cast<std::size_t>(width);
  const auto h = static_cast<std::size_t>(height);
  const auto c = static_cast<std::size_t>(channels);
  const auto wo = static_cast<std::size_t>(std::max(geometry.output_width, 0));
  const auto ci_width =
      static_cast<std::size_t>(std::max(geometry.output_width - 2 * geometry.blur_length, 0));
  const std::size_t input = w * h * c * sizeof(double);
  const std::size_t outputs =
      ((trials > 1 ? 2 : 1) * sizeof(double) + (keep_observed ? sizeof(double) : 1)) * wo * h * c;
  // RMSE_CI (metrics.h): 16 bytes and at most 1 bit a pixel of one
  // channel's window (its records, a's group starts), and buffers of a
  // bounded size: two threads' level counts (1 MiB) and sorters (1.75
  // MiB), the groups of an 8- or 16-bit ground truth (at most 65536: 1.25
  // MiB with their values and starts), b's tied runs (512 KiB), the 16-bit
  // levels (512 KiB): 5 MiB, 5.5 with the allocator's.
  const std::size_t ci_pixels = ci_width * h;
  const std::size_t midway = 16 * ci_pixels + ci_pixels / 8 + (std::size_t{11} << 19);
  // The four image PNGs, each at most a byte a sample (ISA-L stores what it
  // cannot compress), encoded row by row straight into their files' bytes:
  // no raster of samples, no copy (src/io/png_write.cpp); and the encoders'
  // own buffers (ISA-L's state, a block of rows, a chunk of stream), about
  // 1.1 MiB for each PNG encoded at once, at most five.
  const std::size_t encoders = std::size_t{6} << 20;
  const std::size_t encoding = (4 + extra_encoding_bytes_per_sample) * wo * h * c + encoders;
  return kBaselineMemoryBytes + input + outputs + std::max(midway, encoding);
}

std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry,
                                          const SimulationOptions& options, int code_length,
                                          const ObservedRowSink* observed_sink,
                                          std::size_t extra_encoding_bytes_per_sample) {
  return estimate_working_memory_bytes(width, height, channels, geometry, options.trials,
                                       observed_sink, extra_encoding_bytes_per_sample) +
         RowPipeline::plan_bytes(width, height, channels, options, code_length);
}

Image groundtruth_image(const Image& input, const SimulationReport& report) {
  return crop_columns(input, report.output_first_column(), report.geometry.output_width);
}

Image residual_image(const Image& input, const SimulationReport& report) {
  return residual_display(groundtruth_image(input, report), report.restored);
}

std::string SimulationReport::FullReport() const {
  std::ostringstream out;
  out << "fssim simulation report\n";
  out << "  input            " << width << " x " << height << ", " << channels
      << (channels == 1 ? " channel\n" : " channels\n");
  out << "  code             " << code_name << " (L = " << gains.size()
      << ", sum = " << format_number(gain_sum(gains))
      << ", normalized L1 = " << format_number(normalized_l1(gains)) << ")\n";
  out << "  mode             " << to_string(options.mode) << ", velocity "
      << format_number(options.velocity_px_per_slot)
      << (options.restore_velocity_px_per_slot
              ? " (restored as " + format_number(*options.restore_velocity_px_per_slot) + ")"
              : std::string())
      << ", dt " << format_number(options.dt) << ", snr " << format_number(options.snr)
      << ", noise " << to_string(options.noise) << ", seed " << options.seed << "\n";
  if (options.sensor.enabled()) {  // docs/method.md §10
    const SensorModel& s = options.sensor;
    out << "  sensor           read noise " << format_number(s.read_noise_electrons)
        << " e-, dark current " << format_number(s.dark_current_electrons_per_slot)
        << " e-/slot, full well "
        << (s.full_well_electrons ? format_number(*s.full_well_electrons) + " e-" : "none")
        << ", ADC "
        << (s.adc_bits != 0 ? std::to_string(s.adc_bits) + " bits, " +
                                  format_number(s.adc_gain_electrons_per_count) + " e-/count"
                            : "none")
        << "\n";
  }
  out << "  geometry         B = " << geometry.blur_length << ", observed crop "
      << geometry.observed_width << ", deconvolution grid " << geometry.mirror_width << ", output "
      << geometry.output_width << "\n";
  out << "  windows          RMSE columns [" << rmse_first << ", " << rmse_end
      << "), RMSE_CI columns [" << rmse_ci_first << ", " << rmse_ci_end << ")\n";
  out << "  kernel           K(0) = " << format_number(kernel.k0)
      << ", min |K| = " << format_number(kernel.min_abs)
      << " at xi = " << format_number(kernel.min_abs_xi)
      << (kernel.invertible ? ", invertible\n" : ", NOT invertible\n");
  out << "  measured         RMSE " << format_number(metrics.rmse) << " (PSNR "
      << format_number(metrics.psnr) << "), RMSE_CI " << format_number(metrics.rmse_ci) << " (PSNR "
      << format_number(metrics.psnr_ci) << ")\n";
  if (trials.n > 1) {
    out << "  trials           n = " << trials.n << ", RMSE " << format_number(trials.rmse_mean)
        << " +/- " << format_number(trials.rmse_sd) << ", RMSE_CI "
        << format_number(trials.rmse_ci_mean) << " +/- " << format_number(trials.rmse_ci_sd)
        << "\n";
  }
  if (prediction.finite) {
    out << "  predicted        RMSE " << format_number(prediction.rmse) << " = sqrt("
        << format_number(prediction.rmse_noise_free) << "^2 + " << format_number(prediction.noise)
        << (prediction.exact ? "^2), the exact expectation\n"
                             : "^2), approximate: the sensor clips readouts\n");
    out << "  stationary       RMSE " << format_number(prediction.rmse_stationary) << " = sqrt("
        << format_number(prediction.rmse_noise_free) << "^2 + " << format_number(prediction.sigma)
        << "^2), SNR at level 100 " << format_number(prediction.snr_level100) << "\n";
  } else {
    out << "  predicted        none: the code is not invertible (infinite noise)\n";
  }
  for (const auto& w : warnings) out << "  warning          " << w << "\n";
  return out.str();
}

}  // namespace fss
