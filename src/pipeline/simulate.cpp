#include "fss/pipeline/simulate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/metrics.h"
#include "pipeline/row_pipeline.h"

namespace fss {

std::string to_string(NoiseModel noise) {
  switch (noise) {
    case NoiseModel::kNone:
      return "none";
    case NoiseModel::kAggregated:
      return "aggregated";
    case NoiseModel::kPoisson:
      break;
  }
  return "poisson";
}

std::optional<NoiseModel> noise_model_from_string(std::string_view text) {
  if (text == "poisson") return NoiseModel::kPoisson;
  if (text == "none") return NoiseModel::kNone;
  if (text == "aggregated") return NoiseModel::kAggregated;
  return std::nullopt;
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
  const std::string margin = std::to_string(rmse_margin_columns);
  return !(broken("noise", to_string(noise),
                  noise_rule(noise == NoiseModel::kAggregated, mode == ShutterMode::kAnalog)) ||
           broken("rmse_margin_columns", margin, margin_rule(rmse_margin_columns)) ||
           broken("trials", std::to_string(trials), trials_rule(trials)) ||
           broken("threads", std::to_string(threads), threads_rule(threads)));
}

void check_code_for_mode(const ShutterCode& code, ShutterMode mode) {
  if (code.gains.empty()) throw_usage_error("code '" + code.name + "' has no gains");
  if (code.gains.size() > static_cast<std::size_t>(kMaxCodeLength)) {
    throw_usage_error("code '" + code.name + "' has " + std::to_string(code.gains.size()) +
                      " gains, more than " + std::to_string(kMaxCodeLength) +
                      " (the longest code fssim analyses)");
  }
  for (std::size_t k = 0; k < code.gains.size(); ++k) {
    if (!std::isfinite(code.gains[k])) {
      throw_usage_error("code '" + code.name + "': gain " + std::to_string(k) + " is " +
                        format_exact(code.gains[k]) + ", gains must be finite");
    }
  }
  const double largest = gain_max_abs(code.gains);
  if (largest == 0.0) {
    throw_usage_error("code '" + code.name +
                      "' has only zero gains: its transfer function is 0 and nothing is observed");
  }
  // sup |alpha| in [1e-100, 1e100] (L <= 1024): sum alpha, sum alpha^2 and
  // |K| stay finite and nonzero, as dt and snr do within the same range.
  if (const std::string rule = scale_rule(largest); !rule.empty()) {
    throw_usage_error("code '" + code.name + "': its largest |gain| " + format_exact(largest) +
                      " is out of range: it " + rule + " (scale the gains)");
  }
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < code.gains.size(); ++k) {
      const double g = code.gains[k];
      if (!(g >= 0.0 && g <= 1.0)) {
        throw_usage_error("code '" + code.name + "' cannot be used in analog mode: gain " +
                          std::to_string(k) + " is " + format_exact(g) +
                          ", analog gains must lie in [0, 1] (use --mode numerical)");
      }
    }
  }
}

namespace {

void check_inputs(const SimulationOptions& options, const Image& input, const ShutterCode& code) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  check_code_for_mode(code, options.mode);
  if (input.channels != 1 && input.channels != 3) {
    throw_usage_error("input has " + std::to_string(input.channels) +
                      " channels, expected 1 (gray) or 3 (RGB)");
  }
}

// Refuses, before anything is allocated, a run over options.max_memory_bytes.
void check_memory(const SimulationOptions& options, const Image& input, const Geometry& g,
                  const ObservedRowSink* observed_sink) {
  if (options.max_memory_bytes == 0) return;
  const std::size_t needed = estimate_working_memory_bytes(
      input.width, input.height, input.channels, g, options.trials, observed_sink);
  if (needed > options.max_memory_bytes) {
    const auto sizes = format_bytes_distinct(static_cast<double>(needed),
                                             static_cast<double>(options.max_memory_bytes));
    throw_limit_error("a run on this " + std::to_string(input.width) + " x " +
                      std::to_string(input.height) + " x " + std::to_string(input.channels) +
                      " image needs about " + sizes.first +
                      " of memory, more than the memory limit of " + sizes.second);
  }
}

// The kernel the restoration inverts, K at the restore velocity v_r
// (docs/method.md §1), the divisor of the observed image, and their warnings.
void analyze_restoration_kernel(const ShutterCode& code, double v_r, SimulationReport& report) {
  const double dt = report.options.dt;
  report.kernel = analyze_kernel(code.gains, v_r, dt);
  if (!report.kernel.invertible) {
    report.warnings.push_back("code '" + code.name + "' is not invertible at velocity " +
                              format_exact(v_r) +
                              ": min |K| = " + format_number(report.kernel.min_abs) +
                              " at xi = " + format_number(report.kernel.min_abs_xi) +
                              "; the restoration amplifies noise without bound and no finite "
                              "error prediction exists");
  }
  report.observed_divisor = report.kernel.k0;
  if (report.observed_divisor == 0.0) {
    report.observed_divisor = dt * gain_max_abs(code.gains);
    report.warnings.push_back(
        "K(0) = dt * sum of gains is 0: observed.png is divided by dt * max |gain| = " +
        format_number(report.observed_divisor) + " instead");
  }
}

// The plan of a run: geometry and metric windows (docs/method.md §4, §5),
// the memory guard, the kernel and its warnings. Nothing is allocated yet.
SimulationReport plan(const SimulationOptions& options, const Image& input, const ShutterCode& code,
                      const ObservedRowSink* observed_sink) {
  SimulationReport report;
  report.options = options;
  report.options.trial_callback = nullptr;
  report.code_name = code.name;
  report.gains = code.gains;
  report.width = input.width;
  report.height = input.height;
  report.channels = input.channels;
  const double v = options.velocity_px_per_slot;
  const double v_r = options.restore_velocity_px_per_slot.value_or(v);
  // The blur length B covers both velocities.
  report.geometry = Geometry::compute(input.width, code.length(),
                                      std::max(std::abs(v), std::abs(v_r)), options.dt);
  const MetricWindows windows = metric_windows(report.geometry, options.rmse_margin_columns);
  check_memory(options, input, report.geometry, observed_sink);
  report.rmse_first = windows.rmse_first;
  report.rmse_end = windows.rmse_end;
  report.rmse_ci_first = windows.ci_first;
  report.rmse_ci_end = windows.ci_end;
  analyze_restoration_kernel(code, v_r, report);
  return report;
}

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
                    const Image& input, SimulationReport& report, ObservedRowSink* observed) {
  const bool observed_finite = pipeline.restore_all(std::nullopt, report.restored, observed);
  report.metrics = measure(report, input, report.restored);
  report.trials = {options.trials, report.metrics.rmse, 0.0, report.metrics.rmse_ci, 0.0};
  if (options.trial_callback) options.trial_callback(options.trials, options.trials);
  return observed_finite;
}

// Trial t has the noise of seed + t; the first one's images and metrics are
// the report's. False when an observed value is not finite.
bool run_trials(const RowPipeline& pipeline, const SimulationOptions& options, const Image& input,
                SimulationReport& report, ObservedRowSink* observed) {
  const int n = options.trials;
  Image later_trial;  // restoration of the trials after the first, when there are any
  TrialSums sums;
  bool observed_finite = true;
  for (int t = 0; t < n; ++t) {
    if (t == 1) later_trial = Image(report.restored.width, input.height, input.channels);
    Image& restored = t == 0 ? report.restored : later_trial;
    const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(t);
    observed_finite =
        pipeline.restore_all(seed, restored, t == 0 ? observed : nullptr) && observed_finite;
    const Metrics m = measure(report, input, restored);
    if (t == 0) report.metrics = m;
    sums.add(m);
    if (options.trial_callback) options.trial_callback(t + 1, n);
  }
  report.trials = sums.statistics(n);
  return observed_finite;
}

// Extreme gains (1e-320, 1e308) can leave the range of doubles: an error,
// never a silent NaN.
void check_finite(const SimulationReport& report, const ShutterCode& code, bool observed_finite) {
  const auto finite = [](double value) { return std::isfinite(value); };
  if (finite(report.metrics.rmse) && finite(report.metrics.rmse_ci) &&
      finite(report.trials.rmse_mean) && observed_finite &&
      std::all_of(report.restored.data.begin(), report.restored.data.end(), finite)) {
    return;
  }
  double smallest = 0.0;
  for (const double gain : code.gains) {
    if (gain != 0.0 && (smallest == 0.0 || std::abs(gain) < smallest)) smallest = std::abs(gain);
  }
  throw_usage_error("the simulation left the range of double-precision numbers (RMSE " +
                    format_exact(report.metrics.rmse) + "): the gains of code '" + code.name +
                    "' (|gain| from " + format_exact(smallest) + " to " +
                    format_exact(gain_max_abs(code.gains)) + "), dt " +
                    format_exact(report.options.dt) + " or snr " +
                    format_exact(report.options.snr) + " are too extreme");
}

}  // namespace

SimulationReport Simulate(const SimulationOptions& options, const Image& input,
                          const ShutterCode& code, ObservedRowSink* observed_sink) {
  check_inputs(options, input, code);
  // Plan: geometry, metric windows, memory guard, kernel and warnings.
  SimulationReport report = plan(options, input, code, observed_sink);

  // Row pipeline: observe -> noise -> restore, row by row.
  const RowPipeline pipeline(input, code, options, report.geometry, report.observed_divisor);
  if (pipeline.zero_bins() > 0) {
    report.zero_bins = pipeline.zero_bins();
    report.warnings.push_back(std::to_string(report.zero_bins) +
                              " frequencies have K = 0 exactly on the deconvolution grid; they "
                              "are left at 0 in the restoration");
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
    observed_finite = run_noise_free(pipeline, options, input, report, observed_sink);
    noise_free.rmse = report.metrics.rmse;
  } else {
    noise_free = pipeline.noise_free_pass(report.rmse_first, report.rmse_end);
    observed_finite = run_trials(pipeline, options, input, report, observed_sink);
  }
  check_finite(report, code, observed_finite);

  // Prediction (docs/method.md §6, §6b): E[MSE] = RMSE_0^2 + sum_j W(j) S(j) / count,
  // and the stationary approximation RMSE_0^2 + m Q (100 / snr^2) M.
  report.prediction = predict(report, input, noise_free);
  return report;
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
  // RMSE_CI (metrics.h): 16 bytes a pixel and a sorter buffer of half a byte
  // a pixel, at least 2 MiB; 20 bytes and two buffers when a and b are sorted
  // at the same time (windows of at most kParallelSortPixels).
  const std::size_t ci_pixels = ci_width * h;
  const std::size_t sorter = std::max<std::size_t>(ci_pixels / 2, std::size_t{2} << 20);
  // Plus the group bookkeeping of the tie expectation: two bits a pixel and
  // 8 bytes per distinct ground-truth value (at most 65536 of them).
  const std::size_t groups = ci_pixels / 4 + 8 * std::size_t{65536};
  const std::size_t midway =
      (ci_pixels <= kParallelSortPixels ? 20 * ci_pixels + 2 * sorter : 16 * ci_pixels + sorter) +
      groups;
  // Four 8-bit rasters and their encoded copies, at most.
  const std::size_t encoding = (8 + extra_encoding_bytes_per_sample) * wo * h * c;
  return kBaselineMemoryBytes + input + outputs + std::max(midway, encoding);
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
        << "^2), the exact expectation\n";
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
