#include "pipeline/finite_checks.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"

namespace fss {

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
  const bool mse_finite =
      finite(report.trials.mse_mean.value_or(0.0)) && finite(report.trials.mse_sd.value_or(0.0));
  if (ssim_finite && mse_finite && finite(report.metrics.rmse) && finite(report.metrics.rmse_ci) &&
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
    for (const double value : {p.m_amplification, p.noise, p.rmse, p.sigma, p.rmse_stationary,
                               p.snr_level100, p.mse.value_or(0.0)}) {
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

}  // namespace fss
