#include "fss/simulate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "fss/error.h"
#include "fss/metrics.h"
#include "fss/observe.h"
#include "fss/parallel.h"
#include "fss/transfer.h"

namespace fss {

std::string to_string(NoiseModel noise) { return noise == NoiseModel::kNone ? "none" : "poisson"; }

std::optional<NoiseModel> noise_model_from_string(std::string_view text) {
  if (text == "poisson") return NoiseModel::kPoisson;
  if (text == "none") return NoiseModel::kNone;
  return std::nullopt;
}

namespace {
std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}
}  // namespace

bool SimulationOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!std::isfinite(velocity_px_per_slot)) {
    return fail("velocity_px_per_slot = " + number(velocity_px_per_slot) +
                ": must be a finite number");
  }
  if (!(std::isfinite(dt) && dt > 0.0))
    return fail("dt = " + number(dt) + ": must be finite and > 0");
  if (!(std::isfinite(snr) && snr > 0.0)) {
    return fail("snr = " + number(snr) + ": must be finite and > 0");
  }
  if (rmse_margin_columns < -1) {
    return fail("rmse_margin_columns = " + std::to_string(rmse_margin_columns) +
                ": must be >= 0 (or -1 for the default 3B)");
  }
  if (trials < 1) return fail("trials = " + std::to_string(trials) + ": must be >= 1");
  if (threads < 0) return fail("threads = " + std::to_string(threads) + ": must be >= 0 (0: all)");
  return true;
}

namespace {

void check_code(const SimulationOptions& options, const ShutterCode& code) {
  if (code.gains.empty()) throw_usage_error("code '" + code.name + "' has no gains");
  if (gain_max_abs(code.gains) == 0.0) {
    throw_usage_error("code '" + code.name +
                      "' has only zero gains: its transfer function is 0 and nothing is observed");
  }
  if (options.mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < code.gains.size(); ++k) {
      const double g = code.gains[k];
      if (!(g >= 0.0 && g <= 1.0)) {
        throw_usage_error("code '" + code.name + "' cannot be used in analog mode: gain " +
                          std::to_string(k) + " is " + number(g) +
                          ", analog gains must lie in [0, 1] (use --mode numerical)");
      }
    }
  }
}

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
    const int needed = 3 * b + 2 * margin + 1;
    throw_usage_error("image width " + std::to_string(g.width) +
                      " is too narrow for the RMSE window: blur length B = " + std::to_string(b) +
                      " and margin " + std::to_string(margin) + " need a width of at least " +
                      std::to_string(needed) + " (3B + 2 margin + 1); choose a margin below " +
                      std::to_string((g.output_width + 1) / 2) + " with --rmse-margin");
  }
  return w;
}

Metrics measure(const Restoration& r, const Windows& w) {
  Metrics m;
  m.rmse = rmse(r.groundtruth, r.restored, w.rmse_first, w.rmse_end);
  m.psnr = psnr(m.rmse);
  m.rmse_ci = rmse_contrast_invariant(r.groundtruth, r.restored, w.ci_first, w.ci_end);
  m.psnr_ci = psnr(m.rmse_ci);
  return m;
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
  check_code(options, code);
  if (input.channels != 1 && input.channels != 3) {
    throw_usage_error("input has " + std::to_string(input.channels) +
                      " channels, expected 1 (gray) or 3 (RGB)");
  }

  SimulationReport report;
  report.options = options;
  report.options.trial_callback = nullptr;
  report.code_name = code.name;
  report.gains = code.gains;
  report.width = input.width;
  report.height = input.height;
  report.channels = input.channels;

  const double v = options.velocity_px_per_slot;
  const double dt = options.dt;
  const std::vector<double>& gains = code.gains;
  report.geometry = Geometry::compute(input.width, code.length(), v, dt);
  const Windows windows = metric_windows(options, report.geometry);
  report.rmse_first = windows.rmse_first;
  report.rmse_end = windows.rmse_end;
  report.rmse_ci_first = windows.ci_first;
  report.rmse_ci_end = windows.ci_end;

  report.kernel = analyze_kernel(gains, v, dt);
  if (!report.kernel.invertible) {
    report.warnings.push_back("code '" + code.name + "' is not invertible at velocity " +
                              number(v) + ": min |K| = " + number(report.kernel.min_abs) +
                              " at xi = " + number(report.kernel.min_abs_xi) +
                              "; the restoration amplifies noise without bound and no finite "
                              "error prediction exists");
  }
  report.observed_divisor = report.kernel.k0;
  if (report.observed_divisor == 0.0) {
    report.observed_divisor = dt * gain_max_abs(gains);
    report.warnings.push_back(
        "K(0) = dt * sum of gains is 0: observed.png is divided by dt * max "
        "|gain| = " +
        number(report.observed_divisor) + " instead");
  }

  const RowSpectra spectra = row_spectra(input, options.threads);
  ObservationParams params;
  params.velocity = v;
  params.dt = dt;
  params.snr = options.snr;
  params.threads = options.threads;

  // The noise-free run of the same pipeline: RMSE_0 of the prediction.
  const Image noise_free_observation = observe_noise_free(spectra, gains, options.mode, params);
  Restoration noise_free =
      restore(noise_free_observation, input, report.geometry, gains, v, dt, options.threads);
  report.zero_bins = noise_free.zero_bins;
  if (report.zero_bins > 0) {
    report.warnings.push_back(std::to_string(report.zero_bins) +
                              " frequencies have K = 0 exactly on the deconvolution grid; they "
                              "are left at 0 in the restoration");
  }
  const double rmse_noise_free =
      rmse(noise_free.groundtruth, noise_free.restored, windows.rmse_first, windows.rmse_end);

  Restoration first;
  double sum = 0.0, sum_sq = 0.0, sum_ci = 0.0, sum_ci_sq = 0.0;
  for (int t = 0; t < options.trials; ++t) {
    Restoration r;
    if (options.noise == NoiseModel::kNone) {
      r = noise_free;
    } else {
      params.seed = options.seed + static_cast<std::uint64_t>(t);
      const Image observation = options.mode == ShutterMode::kAnalog
                                    ? observe_analog(spectra, gains, params)
                                    : observe_numerical(spectra, gains, params);
      r = restore(observation, input, report.geometry, gains, v, dt, options.threads);
    }
    const Metrics m = measure(r, windows);
    sum += m.rmse;
    sum_sq += m.rmse * m.rmse;
    sum_ci += m.rmse_ci;
    sum_ci_sq += m.rmse_ci * m.rmse_ci;
    if (t == 0) {
      report.metrics = m;
      first = std::move(r);
    }
    if (options.trial_callback) options.trial_callback(t + 1, options.trials);
  }
  const int n = options.trials;
  report.trials = {n, sum / n, sample_sd(sum, sum_sq, n), sum_ci / n,
                   sample_sd(sum_ci, sum_ci_sq, n)};

  // Prediction (SPEC 6): E[RMSE^2] = RMSE_0^2 + m Q (100 / snr^2) M.
  Prediction& p = report.prediction;
  p.finite = report.kernel.invertible;
  p.window_mean = window_mean(first.groundtruth, windows.rmse_first, windows.rmse_end);
  p.q = noise_gain(gains, dt, options.mode);
  p.m_amplification = p.finite ? mean_inverse_power(gains, v, dt, report.geometry.mirror_width)
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

  report.observed = scaled(first.observed, 1.0 / report.observed_divisor);
  report.residual = residual_display(first.groundtruth, first.restored);
  report.restored = std::move(first.restored);
  report.groundtruth = std::move(first.groundtruth);
  return report;
}

std::string SimulationReport::FullReport() const {
  std::ostringstream out;
  out << "fssim simulation report\n";
  out << "  input            " << width << " x " << height << ", " << channels
      << (channels == 1 ? " channel\n" : " channels\n");
  out << "  code             " << code_name << " (L = " << gains.size()
      << ", sum = " << number(gain_sum(gains))
      << ", normalized L1 = " << number(normalized_l1(gains)) << ")\n";
  out << "  mode             " << to_string(options.mode) << ", velocity "
      << number(options.velocity_px_per_slot) << ", dt " << number(options.dt) << ", snr "
      << number(options.snr) << ", noise " << to_string(options.noise) << ", seed " << options.seed
      << "\n";
  out << "  geometry         B = " << geometry.blur_length << ", observed crop "
      << geometry.observed_width << ", deconvolution grid " << geometry.mirror_width << ", output "
      << geometry.output_width << "\n";
  out << "  windows          RMSE columns [" << rmse_first << ", " << rmse_end
      << "), RMSE_CI columns [" << rmse_ci_first << ", " << rmse_ci_end << ")\n";
  out << "  kernel           K(0) = " << number(kernel.k0)
      << ", min |K| = " << number(kernel.min_abs) << " at xi = " << number(kernel.min_abs_xi)
      << (kernel.invertible ? ", invertible\n" : ", NOT invertible\n");
  out << "  measured         RMSE " << number(metrics.rmse) << " (PSNR " << number(metrics.psnr)
      << "), RMSE_CI " << number(metrics.rmse_ci) << " (PSNR " << number(metrics.psnr_ci) << ")\n";
  if (trials.n > 1) {
    out << "  trials           n = " << trials.n << ", RMSE " << number(trials.rmse_mean) << " +/- "
        << number(trials.rmse_sd) << ", RMSE_CI " << number(trials.rmse_ci_mean) << " +/- "
        << number(trials.rmse_ci_sd) << "\n";
  }
  if (prediction.finite) {
    out << "  predicted        RMSE " << number(prediction.rmse) << " = sqrt("
        << number(prediction.rmse_noise_free) << "^2 + " << number(prediction.sigma)
        << "^2), SNR at level 100 " << number(prediction.snr_level100) << "\n";
  } else {
    out << "  predicted        none: the code is not invertible (infinite noise)\n";
  }
  for (const auto& w : warnings) out << "  warning          " << w << "\n";
  return out.str();
}

}  // namespace fss
