#include "fss/io/report_json.h"

#include "io/report_json_value.h"

#include <cmath>

#include "fss/model/code.h"

namespace fss {

namespace {

using nlohmann::json;

// JSON has no infinity: an infinite or NaN value is written as null.
json finite_or_null(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

// Under a velocity distribution (docs/method.md §13): the distribution, and the velocities as
// the trials drew them (velocity null; restore_velocity null unless given).
void add_distribution_parameters(const SimulationReport& r, json& j) {
  const SimulationOptions& o = r.options;
  j["velocity"] = nullptr;
  j["restore_velocity"] =
      o.restore_velocity_px_per_slot ? json(*o.restore_velocity_px_per_slot) : json(nullptr);
  j["velocity_distribution"] = {{"text", o.velocity_distribution->text()},
                                {"description", o.velocity_distribution->describe()}};
}

json parameters_json(const SimulationReport& r) {
  const SimulationOptions& o = r.options;
  json j = {{"code", r.code_name},
            {"code_length", r.gains.size()},
            {"mode", to_string(o.mode)},
            {"velocity", o.velocity_px_per_slot},
            {"restore_velocity", o.restore_velocity_px_per_slot.value_or(o.velocity_px_per_slot)},
            {"dt", o.dt},
            {"snr", o.snr},
            {"seed", o.seed},
            {"noise", to_string(o.noise)},
            {"trials", o.trials}};
  if (o.velocity_distribution) add_distribution_parameters(r, j);
  return j;
}

json geometry_json(const SimulationReport& r) {
  return {{"blur_length", r.geometry.blur_length},
          {"observed_width", r.geometry.observed_width},
          {"mirror_width", r.geometry.mirror_width},
          {"output_width", r.geometry.output_width},
          {"output_first_input_column", 3 * r.geometry.half_blur},
          {"rmse_columns", {r.rmse_first, r.rmse_end}},
          {"rmse_ci_columns", {r.rmse_ci_first, r.rmse_ci_end}}};
}

// The predicted error: rmse and noise the exact expectation (docs/method.md
// §6b), sigma and rmse_stationary the stationary approximation (§6).
json prediction_json(const SimulationReport& r) {
  json j = {{"finite", r.prediction.finite},
            {"rmse_noise_free", finite_or_null(r.prediction.rmse_noise_free)},
            {"noise", finite_or_null(r.prediction.noise)},
            {"rmse", finite_or_null(r.prediction.rmse)},
            {"sigma", finite_or_null(r.prediction.sigma)},
            {"rmse_stationary", finite_or_null(r.prediction.rmse_stationary)},
            {"snr_level100", r.options.restoration.method == RestorationMethod::kInverse
                                 ? finite_or_null(r.prediction.snr_level100)
                                 : json(nullptr)},
            {"window_mean", r.prediction.window_mean},
            {"q", r.prediction.q},
            {"m", finite_or_null(r.prediction.m_amplification)}};
  // With an enabled sensor only, so that a default report keeps its bytes.
  if (r.options.sensor.enabled()) j["exact"] = r.prediction.exact;
  // Under a velocity distribution only (docs/method.md §13): E[MSE] over it, null when infinite
  // with the reason.
  if (r.options.velocity_distribution) {
    const Prediction& p = r.prediction;
    j["mse"] = p.mse ? finite_or_null(*p.mse) : json(nullptr);
    j["mse_error_estimate"] = p.mse_error_estimate;
    j["mse_evaluations"] = p.mse_evaluations;
    j["mse_infinite_reason"] =
        p.mse_infinite_reason.empty() ? json(nullptr) : json(p.mse_infinite_reason);
  }
  return j;
}

// The sensor (docs/method.md §10), written only when it is enabled;
// full_well_electrons null for none, adc_bits 0 for no ADC.
json sensor_json(const SensorModel& s) {
  return {{"read_noise_electrons", s.read_noise_electrons},
          {"dark_current_electrons_per_slot", s.dark_current_electrons_per_slot},
          {"full_well_electrons", s.full_well_electrons ? json(*s.full_well_electrons) : json()},
          {"adc_bits", s.adc_bits},
          {"adc_gain_electrons_per_count", s.adc_gain_electrons_per_count}};
}

json optional_json(const std::optional<double>& value) {
  return value ? finite_or_null(*value) : json(nullptr);
}

// The restoration (docs/method.md §12), written only when it is not the inverse filter.
json restoration_json(const RestorationSummary& r) {
  json j = {{"method", to_string(r.options.method)}};
  if (r.options.method == RestorationMethod::kTikhonov) {
    j["regularization"] = optional_json(r.regularization);
    j["regularization_optimal"] = !r.options.regularization.has_value();
  }
  if (r.options.method == RestorationMethod::kWiener) {
    j["prior"] = r.options.prior == PriorKind::kOracle ? "oracle" : "power-law";
    if (r.options.prior == PriorKind::kPowerLaw) {
      j["prior_exponent"] = r.options.prior_exponent;
      j["prior_level"] = optional_json(r.prior_level);
    }
    j["noise_variance"] = optional_json(r.noise_variance);
  }
  return j;
}

}  // namespace

// FSS_VERSION_FULL is defined for this file only (cmake/version.cmake), so
// that a new commit recompiles nothing else of the library.
std::string report_fssim_version() { return FSS_VERSION_FULL; }

json report_json(const SimulationReport& r, const std::string& input_path) {
  json j;
  j["fssim_version"] = report_fssim_version();
  j["schema_version"] = kReportSchemaVersion;
  j["input"] = {
      {"path", input_path}, {"width", r.width}, {"height", r.height}, {"channels", r.channels}};
  j["parameters"] = parameters_json(r);
  if (r.options.sensor.enabled()) j["sensor"] = sensor_json(r.options.sensor);
  j["code"] = {{"name", r.code_name},
               {"gains", r.gains},
               {"sum", gain_sum(r.gains)},
               {"square_sum", gain_square_sum(r.gains)},
               {"normalized_l1", normalized_l1(r.gains)}};
  j["geometry"] = geometry_json(r);
  j["metrics"] = {{"rmse", finite_or_null(r.metrics.rmse)},
                  {"psnr", finite_or_null(r.metrics.psnr)},
                  {"rmse_ci", finite_or_null(r.metrics.rmse_ci)},
                  {"psnr_ci", finite_or_null(r.metrics.psnr_ci)},
                  {"ssim", optional_json(r.metrics.ssim)}};
  j["kernel"] = {{"k0", r.kernel.k0},
                 {"min_abs", r.kernel.min_abs},
                 {"min_abs_xi", r.kernel.min_abs_xi},
                 {"invertible", r.kernel.invertible},
                 {"observed_divisor", r.observed_divisor},
                 {"zero_bins", r.zero_bins}};
  if (r.options.restoration.method != RestorationMethod::kInverse) {
    j["restoration"] = restoration_json(r.restoration);
  }
  j["prediction"] = prediction_json(r);
  j["trials"] = {{"n", r.trials.n},
                 {"rmse_mean", finite_or_null(r.trials.rmse_mean)},
                 {"rmse_sd", finite_or_null(r.trials.rmse_sd)},
                 {"rmse_ci_mean", finite_or_null(r.trials.rmse_ci_mean)},
                 {"rmse_ci_sd", finite_or_null(r.trials.rmse_ci_sd)},
                 {"ssim_mean", optional_json(r.trials.ssim_mean)},
                 {"ssim_sd", optional_json(r.trials.ssim_sd)}};
  if (r.options.velocity_distribution) {
    j["trials"]["mse_mean"] = optional_json(r.trials.mse_mean);
    j["trials"]["mse_sd"] = optional_json(r.trials.mse_sd);
    j["trials"]["velocities"] = r.trial_velocities;
  }
  j["warnings"] = r.warnings;
  return j;
}

std::string report_json_text(const SimulationReport& report, const std::string& input_path) {
  return report_json(report, input_path).dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace fss
