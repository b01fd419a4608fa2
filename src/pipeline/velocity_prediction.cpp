#include "pipeline/velocity_prediction.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/prediction.h"
#include "pipeline/noise_free_run.h"
#include "pipeline/plan_core.h"
#include "pipeline/predict.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/velocity_trials.h"

namespace fss {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// What the noise-free pass at one velocity gives the prediction (docs/method.md §6b).
struct VelocityValue {
  double r0_squared = 0.0;   // RMSE_0(v)^2
  double noise_power = 0.0;  // sum_j W_v(j) S_v(j) / count
  double m = 0.0;            // M: the mean |H|^2 of the filter that restores at v
  bool invertible = true;    // the inverse filter's kernel is (the others are bounded)
  bool clips = false;        // the sensor clips some readout of the observed crop

  double mse() const { return invertible ? r0_squared + noise_power : kInfinity; }
};

// The values at the velocities the quadrature asks for, each computed once.
class VelocityValues {
 public:
  VelocityValues(const PlanCore& plan, const SimulationReport& report, const Image& input,
                 const ShutterCode& code)
      : plan_(plan), report_(report), input_(input), code_(code) {}

  const VelocityValue& at(double velocity) {
    const auto key = std::bit_cast<std::uint64_t>(velocity);
    auto found = values_.find(key);
    if (found == values_.end()) {
      found = values_.emplace(key, evaluate(velocity)).first;
      if (!found->second.invertible && !not_invertible_) not_invertible_ = velocity;
    }
    return found->second;
  }
  int evaluations() const { return static_cast<int>(values_.size()); }
  // The first velocity met whose kernel is not invertible (inverse filter).
  std::optional<double> not_invertible() const { return not_invertible_; }

 private:
  // Observes at `velocity`, restores at it (or the restore velocity) on the run's geometry.
  VelocityValue evaluate(double velocity) const {
    const SimulationOptions o = options_at_velocity(report_.options, velocity);
    const PlanCore core(o, plan_.geometry(), code_, PlanCore::VelocityPart::kPrediction);
    VelocityValue value;
    value.m = core.m_amplification();
    // The support's ends were checked (infinite_reason); a bin where K vanishes makes M infinite.
    if (!std::isfinite(value.m)) {
      value.invertible = false;
      return value;
    }
    const RowPipeline pipeline(input_, core.observer(), *core.restorer(), o, plan_.geometry(),
                               plan_.observed_divisor());
    const bool noisy = o.noise != NoiseModel::kNone;
    const NoiseFreeRun run = pipeline.noise_free_pass(report_.rmse_first, report_.rmse_end, noisy);
    value.r0_squared = run.rmse * run.rmse;
    value.noise_power = noisy ? exact_noise_power(report_, core.noise_weights(), run) : 0.0;
    value.clips = run.saturated_readouts > 0 || run.near_zero_readouts > 0;
    return value;
  }

  const PlanCore& plan_;
  const SimulationReport& report_;
  const Image& input_;
  const ShutterCode& code_;
  std::map<std::uint64_t, VelocityValue> values_;
  std::optional<double> not_invertible_;
};

std::string support_reason(double velocity) {
  return "code not invertible at velocity " + format_number(velocity) + " of the support";
}

// Why E[MSE] is infinite before any pass, "" when it need not be: the inverse filter with a
// kernel that is not invertible at the restore velocity or at an end of the support (min |K|
// over the band falls as |v| grows, so the end of larger |v| is the worst velocity).
std::string infinite_reason(const SimulationOptions& o, const ShutterCode& code) {
  if (o.restoration.method != RestorationMethod::kInverse) return "";
  if (o.restore_velocity_px_per_slot) {
    const double v_r = *o.restore_velocity_px_per_slot;
    return analyze_kernel(code.gains, v_r, o.dt).invertible
               ? ""
               : "code not invertible at the restore velocity " + format_number(v_r);
  }
  const VelocityDistribution& d = *o.velocity_distribution;
  const bool high_first = std::abs(d.high) >= std::abs(d.low);
  for (const double v : {high_first ? d.high : d.low, high_first ? d.low : d.high}) {
    if (!analyze_kernel(code.gains, v, o.dt).invertible) return support_reason(v);
  }
  return "";
}

// The prediction of an infinite E[MSE]: the averaged fields infinite (not computed).
Prediction infinite_prediction(Prediction p, std::string reason) {
  p.finite = false;
  p.mse = kInfinity;
  p.m_amplification = p.rmse_noise_free = p.noise = p.rmse = p.sigma = p.rmse_stationary =
      kInfinity;
  p.snr_level100 = 0.0;
  p.mse_infinite_reason = std::move(reason);
  return p;
}

void add_warnings(const VelocityExpectation& e, int clipping_nodes, int nodes,
                  double relative_tolerance, std::vector<std::string>* warnings) {
  if (warnings == nullptr) return;
  if (clipping_nodes > 0) {
    warnings->push_back(
        "at " + std::to_string(clipping_nodes) + " of the " + std::to_string(nodes) +
        " velocities of the quadrature, the sensor clips readouts (the full well or the ADC's "
        "range, docs/method.md §10): the predicted MSE is approximate");
  }
  if (!e.converged) {
    warnings->push_back(
        "the quadrature of the expected MSE over the velocity distribution did not reach the "
        "relative tolerance " +
        format_number(relative_tolerance) + " within " + std::to_string(e.intervals) +
        " intervals (error estimate " + format_number(e.error_estimate) +
        ", docs/method.md §13): the predicted MSE is approximate");
  }
}

}  // namespace

Prediction predict_over_velocities(const PlanCore& plan, const SimulationReport& report,
                                   const Image& input, const ShutterCode& code,
                                   double relative_tolerance, std::vector<std::string>* warnings,
                                   int max_intervals) {
  const SimulationOptions& o = report.options;
  Prediction p;
  const int first = report.output_first_column();
  p.window_mean = window_mean(input, first + report.rmse_first, first + report.rmse_end);
  p.q = noise_gain(code.gains, o.dt, o.mode);
  std::string reason = infinite_reason(o, code);
  if (!reason.empty()) return infinite_prediction(p, reason);
  VelocityValues values(plan, report, input, code);
  std::vector<VelocityNode> rule;
  const VelocityExpectation e = expected_over_velocity(
      *o.velocity_distribution, [&](double v) { return values.at(v).mse(); }, relative_tolerance,
      max_intervals, &rule, kInitialVelocityQuadratureIntervals);
  if (const std::optional<double> v = values.not_invertible()) {
    p.mse_evaluations = values.evaluations();
    return infinite_prediction(p, support_reason(*v));
  }
  // The other fields at the final rule's nodes and weights (prediction.h).
  double r0_squared = 0.0, noise_power = 0.0, m = 0.0;
  int clipping_nodes = 0;
  for (const VelocityNode& node : rule) {
    const VelocityValue& value = values.at(node.velocity);
    r0_squared += node.weight * value.r0_squared;
    noise_power += node.weight * value.noise_power;
    m += node.weight * value.m;
    clipping_nodes += value.clips ? 1 : 0;
  }
  const bool noisy = o.noise != NoiseModel::kNone;
  p.mse_evaluations = values.evaluations();
  p.finite = true;
  p.mse = e.value;
  p.mse_error_estimate = e.error_estimate;
  p.rmse = std::sqrt(e.value);
  p.m_amplification = m;
  p.rmse_noise_free = std::sqrt(r0_squared);
  p.noise = std::sqrt(noise_power);
  p.sigma = noisy ? noise_sigma(p.window_mean, code.gains, o.dt, o.mode, m, o.snr, o.sensor) : 0.0;
  p.rmse_stationary = std::sqrt(r0_squared + p.sigma * p.sigma);
  p.snr_level100 = o.restoration.method == RestorationMethod::kInverse
                       ? snr_level100(code.gains, o.dt, o.mode, m, o.snr, o.sensor)
                       : 0.0;
  p.exact = clipping_nodes == 0;
  add_warnings(e, clipping_nodes, static_cast<int>(rule.size()), relative_tolerance, warnings);
  return p;
}

}  // namespace fss
