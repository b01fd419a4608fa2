#include "fss/pipeline/simulate.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "fss/core/error.h"
#include "fss/core/parallel.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/observe.h"
#include "fss/pipeline/restore.h"

namespace fss {

std::string to_string(NoiseModel noise) { return noise == NoiseModel::kNone ? "none" : "poisson"; }

std::optional<NoiseModel> noise_model_from_string(std::string_view text) {
  if (text == "poisson") return NoiseModel::kPoisson;
  if (text == "none") return NoiseModel::kNone;
  return std::nullopt;
}

bool SimulationOptions::IsValid(std::string* error) const {
  // True, with the message, when `rule` (option_rules.h) is broken.
  const auto broken = [&](const char* field, const std::string& value, const std::string& rule) {
    if (rule.empty()) return false;
    if (error) *error = std::string(field) + " = " + value + ": " + rule;
    return true;
  };
  if (broken("velocity_px_per_slot", format_number(velocity_px_per_slot),
             velocity_rule(velocity_px_per_slot))) {
    return false;
  }
  if (restore_velocity_px_per_slot &&
      broken("restore_velocity_px_per_slot", format_number(*restore_velocity_px_per_slot),
             velocity_rule(*restore_velocity_px_per_slot))) {
    return false;
  }
  // The sign of either scale is reported before the range of either.
  for (const bool positive : {false, true}) {
    if (scale_is_positive(dt) == positive && broken("dt", format_number(dt), scale_rule(dt))) {
      return false;
    }
    if (scale_is_positive(snr) == positive && broken("snr", format_number(snr), scale_rule(snr))) {
      return false;
    }
  }
  const std::string margin = std::to_string(rmse_margin_columns);
  return !(broken("rmse_margin_columns", margin, margin_rule(rmse_margin_columns)) ||
           broken("trials", std::to_string(trials), trials_rule(trials)) ||
           broken("threads", std::to_string(threads), threads_rule(threads)));
}

void check_code_for_mode(const ShutterCode& code, ShutterMode mode) {
  if (code.gains.empty()) throw_usage_error("code '" + code.name + "' has no gains");
  if (gain_max_abs(code.gains) == 0.0) {
    throw_usage_error("code '" + code.name +
                      "' has only zero gains: its transfer function is 0 and nothing is observed");
  }
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < code.gains.size(); ++k) {
      const double g = code.gains[k];
      if (!(g >= 0.0 && g <= 1.0)) {
        throw_usage_error("code '" + code.name + "' cannot be used in analog mode: gain " +
                          std::to_string(k) + " is " + format_number(g) +
                          ", analog gains must lie in [0, 1] (use --mode numerical)");
      }
    }
  }
}

namespace {

struct Windows {
  int rmse_first, rmse_end, ci_first, ci_end;
};

Windows metric_windows(const SimulationOptions& options, const Geometry& g) {
  const int b = g.blur_length;
  const int margin = options.rmse_margin_columns < 0 ? 3 * b : options.rmse_margin_columns;
  Windows w{margin, g.output_width - margin, b, g.output_width - b};
  // The RMSE_CI window [B, Wo - B) needs W > 5B whatever the margin.
  if (w.ci_first >= w.ci_end) {
    throw_usage_error(
        "image width " + std::to_string(g.width) +
        " is too narrow for blur length B = " + std::to_string(b) +
        ": the contrast-invariant RMSE window [B, W - 4B) needs a width of at least " +
        std::to_string(5 * b + 1) + " (5B + 1), which no --rmse-margin can change");
  }
  if (w.rmse_first >= w.rmse_end) {
    const long long needed = 3LL * b + 2LL * margin + 1;
    throw_usage_error("image width " + std::to_string(g.width) +
                      " is too narrow for the RMSE window: blur length B = " + std::to_string(b) +
                      " and margin " + std::to_string(margin) + " need a width of at least " +
                      std::to_string(needed) + " (3B + 2 margin + 1); choose a margin below " +
                      std::to_string((g.output_width + 1) / 2) + " with --rmse-margin");
  }
  return w;
}

double window_mean(const Image& image, int first, int end) {
  // mean per channel, then averaged over channels (equal pixel counts)
  double sum = 0.0;
  for (int c = 0; c < image.channels; ++c) {
    for (int y = 0; y < image.height; ++y) {
      for (int x = first; x < end; ++x) sum += image.at(c, y, x);
    }
  }
  return sum / (static_cast<double>(end - first) * image.height * image.channels);
}

double sample_sd(double sum, double sum_sq, int n) {
  if (n < 2) return 0.0;
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)));
}

}  // namespace

SimulationReport Simulate(const SimulationOptions& options, const Image& input,
                          const ShutterCode& code) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  check_code_for_mode(code, options.mode);
  if (input.channels != 1 && input.channels != 3) {
    throw_usage_error("input has " + std::to_string(input.channels) +
                      " channels, expected 1 (gray) or 3 (RGB)");
  }

  SimulationReport report;
  report.options = options;
  report.options.trial_callback = nullptr;
  report.options.observed_row_callback = nullptr;
  report.code_name = code.name;
  report.gains = code.gains;
  report.width = input.width;
  report.height = input.height;
  report.channels = input.channels;

  const double v = options.velocity_px_per_slot;
  // v_r: the velocity of the kernel the restoration inverts.
  const double v_r = options.restore_velocity_px_per_slot.value_or(v);
  const double dt = options.dt;
  const std::vector<double>& gains = code.gains;
  const Geometry& g = report.geometry =
      Geometry::compute(input.width, code.length(), std::max(std::abs(v), std::abs(v_r)), dt);
  const Windows windows = metric_windows(options, g);
  if (options.max_memory_bytes > 0) {
    const std::size_t needed = estimate_working_memory_bytes(
        input.width, input.height, input.channels, g, options.trials, options.keep_observed);
    if (needed > options.max_memory_bytes) {
      throw_limit_error("a run on this " + std::to_string(input.width) + " x " +
                        std::to_string(input.height) + " x " + std::to_string(input.channels) +
                        " image needs about " + format_bytes(static_cast<double>(needed)) +
                        " of memory, more than the memory limit of " +
                        format_bytes(static_cast<double>(options.max_memory_bytes)));
    }
  }
  report.rmse_first = windows.rmse_first;
  report.rmse_end = windows.rmse_end;
  report.rmse_ci_first = windows.ci_first;
  report.rmse_ci_end = windows.ci_end;

  report.kernel = analyze_kernel(gains, v_r, dt);
  if (!report.kernel.invertible) {
    report.warnings.push_back("code '" + code.name + "' is not invertible at velocity " +
                              format_number(v_r) +
                              ": min |K| = " + format_number(report.kernel.min_abs) +
                              " at xi = " + format_number(report.kernel.min_abs_xi) +
                              "; the restoration amplifies noise without bound and no finite "
                              "error prediction exists");
  }
  report.observed_divisor = report.kernel.k0;
  if (report.observed_divisor == 0.0) {
    report.observed_divisor = dt * gain_max_abs(gains);
    report.warnings.push_back(
        "K(0) = dt * sum of gains is 0: observed.png is divided by dt * max |gain| = " +
        format_number(report.observed_divisor) + " instead");
  }

  // Row-streamed pipeline: each row goes input -> DFT -> observation ->
  // observed crop, mirror, inverse filter -> restored row, so the working
  // memory beyond the outputs is a few rows per thread.
  ObservationParams params;
  params.velocity = v;
  params.dt = dt;
  params.snr = options.snr;
  const RowObserver observer(input.width, gains, options.mode, params);
  const RowRestorer restorer(g, gains, v_r, dt);
  report.zero_bins = restorer.zero_bins();
  if (report.zero_bins > 0) {
    report.warnings.push_back(std::to_string(report.zero_bins) +
                              " frequencies have K = 0 exactly on the deconvolution grid; they "
                              "are left at 0 in the restoration");
  }
  const int offset = report.output_first_column();
  const int rows = input.channels * input.height;
  // One pass over all rows. `restored` (Wo wide) may be null when only the
  // squared errors over the RMSE window are wanted (per row, summed in row
  // order so that the total does not depend on the threads).
  // With `observed`, the observed rows go to report.observed (when kept) and
  // to the row callback, and their finiteness is checked.
  std::atomic<bool> observed_finite{true};
  auto run_pass = [&](bool noisy, std::uint64_t seed, Image* restored, bool observed,
                      std::vector<double>* row_errors) {
    parallel_for(rows, options.threads, [&](int begin, int end) {
      RowObserver::Scratch observer_scratch(observer);
      RowRestorer::Scratch restorer_scratch(restorer);
      std::vector<double> observation(static_cast<std::size_t>(g.width));
      std::vector<double> own_row(restored ? 0 : static_cast<std::size_t>(g.output_width));
      std::vector<double> observed_row(observed ? static_cast<std::size_t>(g.output_width) : 0);
      for (int r = begin; r < end; ++r) {
        const int c = r / input.height;
        const int y = r % input.height;
        observer.load_row(input.row(c, y), observer_scratch);
        observer.observe(noisy, seed, c, y, observer_scratch, observation);
        if (observed) {
          bool finite = true;
          for (int x = 0; x < g.output_width; ++x) {
            observed_row[x] = observation[offset + x] / report.observed_divisor;
            finite = finite && std::isfinite(observed_row[x]);
          }
          if (!finite) observed_finite = false;
          if (options.keep_observed) {
            std::copy(observed_row.begin(), observed_row.end(), report.observed.row(c, y));
          }
          if (options.observed_row_callback) options.observed_row_callback(c, y, observed_row);
        }
        double* out = restored ? restored->row(c, y) : own_row.data();
        restorer.restore(observation.data(), restorer_scratch, out);
        if (row_errors) {
          const double* truth = input.row(c, y) + offset;
          double sum = 0.0;  // as rmse() sums a row
          for (int x = windows.rmse_first; x < windows.rmse_end; ++x) {
            const double d = truth[x] - out[x];
            sum += d * d;
          }
          (*row_errors)[r] = sum;
        }
      }
    });
  };
  auto measure = [&](const Image& restored) {
    Metrics m;
    m.rmse = rmse(input, offset, restored, windows.rmse_first, windows.rmse_end);
    m.psnr = psnr(m.rmse);
    m.rmse_ci = rmse_contrast_invariant(input, offset, restored, windows.ci_first, windows.ci_end,
                                        options.threads);
    m.psnr_ci = psnr(m.rmse_ci);
    return m;
  };

  if (options.keep_observed) report.observed = Image(g.output_width, input.height, input.channels);
  report.restored = Image(g.output_width, input.height, input.channels);
  double rmse_noise_free = 0.0;
  if (options.noise == NoiseModel::kNone) {
    // The noise-free run is every trial: run it once.
    run_pass(false, 0, &report.restored, true, nullptr);
    report.metrics = measure(report.restored);
    rmse_noise_free = report.metrics.rmse;
    report.trials = {options.trials, report.metrics.rmse, 0.0, report.metrics.rmse_ci, 0.0};
    if (options.trial_callback) options.trial_callback(options.trials, options.trials);
  } else {
    // RMSE_0 of the prediction: the same pipeline on the expected observation.
    std::vector<double> row_errors(static_cast<std::size_t>(rows));
    run_pass(false, 0, nullptr, false, &row_errors);
    double total = 0.0;
    for (const double e : row_errors) total += e;
    rmse_noise_free =
        std::sqrt(total / (static_cast<double>(windows.rmse_end - windows.rmse_first) *
                           input.height * input.channels));

    Image later_trial;  // restoration of trials after the first, when there are any
    double sum = 0.0, sum_sq = 0.0, sum_ci = 0.0, sum_ci_sq = 0.0;
    for (int t = 0; t < options.trials; ++t) {
      const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(t);
      if (t == 1) later_trial = Image(g.output_width, input.height, input.channels);
      Image& restored = t == 0 ? report.restored : later_trial;
      run_pass(true, seed, &restored, t == 0, nullptr);
      const Metrics m = measure(restored);
      if (t == 0) report.metrics = m;
      sum += m.rmse;
      sum_sq += m.rmse * m.rmse;
      sum_ci += m.rmse_ci;
      sum_ci_sq += m.rmse_ci * m.rmse_ci;
      if (options.trial_callback) options.trial_callback(t + 1, options.trials);
    }
    const int n = options.trials;
    report.trials = {n, sum / n, sample_sd(sum, sum_sq, n), sum_ci / n,
                     sample_sd(sum_ci, sum_ci_sq, n)};
  }

  // Extreme gains (1e-320, 1e308) can leave the range of doubles: an error,
  // never a silent NaN.
  const auto all_finite = [](const Image& image) {
    return std::all_of(image.data.begin(), image.data.end(),
                       [](double value) { return std::isfinite(value); });
  };
  if (!(std::isfinite(report.metrics.rmse) && std::isfinite(report.metrics.rmse_ci) &&
        std::isfinite(report.trials.rmse_mean) && observed_finite && all_finite(report.restored))) {
    double smallest = 0.0;
    for (const double gain : gains) {
      if (gain != 0.0 && (smallest == 0.0 || std::abs(gain) < smallest)) smallest = std::abs(gain);
    }
    throw_usage_error("the simulation left the range of double-precision numbers (RMSE " +
                      format_number(report.metrics.rmse) + "): the gains of code '" + code.name +
                      "' (|gain| from " + format_number(smallest) + " to " +
                      format_number(gain_max_abs(gains)) + "), dt " + format_number(dt) +
                      " or snr " + format_number(options.snr) + " are too extreme");
  }

  // Prediction (SPEC 6): E[RMSE^2] = RMSE_0^2 + m Q (100 / snr^2) M.
  Prediction& p = report.prediction;
  p.finite = report.kernel.invertible;
  p.window_mean = window_mean(input, offset + windows.rmse_first, offset + windows.rmse_end);
  p.q = noise_gain(gains, dt, options.mode);
  p.m_amplification = p.finite ? mean_inverse_power(gains, v_r, dt, g.mirror_width)
                               : std::numeric_limits<double>::infinity();
  p.rmse_noise_free = rmse_noise_free;
  p.snr_level100 = snr_level100(p.q, p.m_amplification, options.snr);
  p.sigma = options.noise == NoiseModel::kNone
                ? 0.0
                : noise_sigma(p.window_mean, p.q, p.m_amplification, options.snr);
  p.rmse = std::sqrt(rmse_noise_free * rmse_noise_free + p.sigma * p.sigma);
  if (!p.finite) {
    p.sigma = std::numeric_limits<double>::infinity();
    p.rmse = std::numeric_limits<double>::infinity();
  }
  return report;
}

std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry, int trials,
                                          bool keep_observed) {
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
  const std::size_t midway =
      ci_pixels <= kParallelSortPixels ? 20 * ci_pixels + 2 * sorter : 16 * ci_pixels + sorter;
  // Four 8-bit rasters and their encoded copies, at most.
  const std::size_t encoding = 8 * wo * h * c;
  return input + outputs + std::max(midway, encoding);
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
        << format_number(prediction.rmse_noise_free) << "^2 + " << format_number(prediction.sigma)
        << "^2), SNR at level 100 " << format_number(prediction.snr_level100) << "\n";
  } else {
    out << "  predicted        none: the code is not invertible (infinite noise)\n";
  }
  for (const auto& w : warnings) out << "  warning          " << w << "\n";
  return out.str();
}

}  // namespace fss
