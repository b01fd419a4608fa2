// analyze_code under a velocity distribution (design/analyze.h; docs/method.md §13): the
// expected error over the distribution, its worst velocity, and the snapshot's and the bound's
// averages.
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/golden_section.h"
#include "design/analysis_parts.h"
#include "design/velocity_average.h"
#include "fss/core/error.h"
#include "fss/design/analyze.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/prediction.h"

namespace fss {

namespace {

using design_detail::error_of_level100_snr;
using design_detail::kInfinity;
using design_detail::mean_inverse_on_grid;

// A velocity's figures, each as analyze_code computes it at that velocity.
struct AtVelocity {
  double error = 0.0;           // E(v)
  double regularization = 0.0;  // Tikhonov: the lambda of E(v)
  bool invertible = true;
};

// The figures of the code and of the snapshot at any velocity of the support, remembered by
// velocity so that the worst-velocity scan and M's average reuse the quadrature's evaluations.
class VelocityFigures {
 public:
  // `a` holds the setting and the velocity-free figures (effective_q); `each` checks the
  // invertibility at every velocity (a discrete distribution), else a.invertible holds for all.
  VelocityFigures(const std::vector<double>& gains, const CodeAnalysis& a, bool each)
      : gains_(gains), snapshot_(gains.size(), 0.0), a_(a), each_(each) {
    snapshot_[0] = 1.0;
    snapshot_q_ = design_detail::effective_noise_gain(snapshot_, a.dt, a.mode, a.snr, a.sensor);
  }

  const AtVelocity& Code(double v);
  // M(v) of the code, infinite where it is not invertible.
  double InverseM(double v);
  AtVelocity Snapshot(double v) const;
  // The velocities evaluated so far, in increasing order.
  const std::map<double, AtVelocity>& evaluated() const { return code_; }

 private:
  bool Invertible(double v) const {
    return each_ ? analyze_kernel(gains_, v, a_.dt).invertible : a_.invertible;
  }
  bool inverse() const { return a_.restoration.method == RestorationMethod::kInverse; }

  const std::vector<double>& gains_;
  std::vector<double> snapshot_;
  const CodeAnalysis& a_;
  bool each_;
  double snapshot_q_ = 0.0;
  std::map<double, AtVelocity> code_;
  std::map<double, double> m_;
};

// Inverse filter: E(v) = (100 / s)^2, s = snr / sqrt(Q_eff M(v)); else level100_restoration_error.
const AtVelocity& VelocityFigures::Code(double v) {
  if (const auto found = code_.find(v); found != code_.end()) return found->second;
  AtVelocity at;
  if (inverse()) {
    const double m = InverseM(v);
    at.invertible = std::isfinite(m);
    at.error = error_of_level100_snr(snr_level100(a_.effective_q, m, a_.snr));
  } else {
    const RestorationError r =
        level100_restoration_error(gains_, v, a_.dt, a_.snr, a_.mode, a_.restoration, a_.sensor);
    at.error = r.error;
    at.regularization = r.regularization;
    at.invertible = !each_ || Invertible(v);
  }
  return code_.emplace(v, at).first->second;
}

double VelocityFigures::InverseM(double v) {
  if (const auto found = m_.find(v); found != m_.end()) return found->second;
  const double m = Invertible(v) ? mean_inverse_on_grid(gains_, v, a_) : kInfinity;
  m_.emplace(v, m);
  return m;
}

AtVelocity VelocityFigures::Snapshot(double v) const {
  AtVelocity at;
  if (inverse()) {
    const double m = mean_inverse_on_grid(std::vector<double>{1.0}, v, a_);
    at.error = error_of_level100_snr(snr_level100(snapshot_q_, m, a_.snr));
  } else {
    const RestorationError r =
        level100_restoration_error(snapshot_, v, a_.dt, a_.snr, a_.mode, a_.restoration, a_.sensor);
    at.error = r.error;
    at.regularization = r.regularization;
  }
  return at;
}

// The velocity of largest E over the support: the largest of the velocities evaluated and of a
// uniform scan (kWorstVelocityScan intervals), refined by golden-section search between its two
// neighbours; a discrete distribution's largest over its points. The first on ties.
double worst_velocity(const VelocityDistribution& d, VelocityFigures& figures) {
  if (d.kind != VelocityDistributionKind::kDiscrete) {
    for (int i = 0; i <= design_detail::kWorstVelocityScan; ++i) {
      const double t = static_cast<double>(i) / design_detail::kWorstVelocityScan;
      figures.Code(i == design_detail::kWorstVelocityScan ? d.high : d.low + t * (d.high - d.low));
    }
  } else {
    for (const VelocityPoint& p : d.points) figures.Code(p.velocity);
  }
  const std::map<double, AtVelocity>& evaluated = figures.evaluated();
  auto best = evaluated.begin();
  for (auto it = evaluated.begin(); it != evaluated.end(); ++it) {
    if (it->second.error > best->second.error) best = it;
  }
  if (d.kind == VelocityDistributionKind::kDiscrete || !std::isfinite(best->second.error)) {
    return best->first;
  }
  const double left = best == evaluated.begin() ? best->first : std::prev(best)->first;
  const double right = std::next(best) == evaluated.end() ? best->first : std::next(best)->first;
  double worst = best->first;
  const double worst_error = best->second.error;
  const auto [v, minus_error] =
      golden_section_minimum([&figures](double u) { return -figures.Code(u).error; }, left, right,
                             design_detail::kWorstVelocitySteps, 0.0);
  if (-minus_error > worst_error) worst = v;
  return worst;
}

// The analysis of a point distribution: analyze_code at its velocity, bit for bit.
CodeAnalysis point_analysis(const ShutterCode& code, const VelocityDistribution& d, double dt,
                            double snr, ShutterMode mode, int grid, const SensorModel& sensor,
                            const RestorationOptions& restoration) {
  const double v = design_detail::point_velocity(d);
  CodeAnalysis a = analyze_code(code, v, dt, snr, mode, grid, sensor, restoration);
  a.velocity_distribution = d;
  a.worst_velocity = v;
  a.worst_snr_level100 = a.snr_level100;
  a.quadrature_evaluations = 1;
  return a;
}

// E[f(V)] by the adaptive rule (expected_over_velocity).
double averaged(const VelocityDistribution& d, const std::function<double(double)>& f) {
  return expected_over_velocity(d, f).value;
}

// The code's expected error, its quadrature's figures, M's average and invertibility over the
// support into `a`: the adaptive rule (expected_over_velocity); infinite without an evaluation
// when the inverse filter meets a non-invertible continuous support.
void average_code_error(const VelocityDistribution& d, VelocityFigures& figures, CodeAnalysis* a) {
  const bool discrete = d.kind == VelocityDistributionKind::kDiscrete;
  if (a->restoration.method == RestorationMethod::kInverse && !discrete && !a->invertible) {
    a->restoration_error = kInfinity;
    a->m = kInfinity;
    return;
  }
  std::vector<VelocityNode> rule;
  const VelocityExpectation e = expected_over_velocity(
      d, [&figures](double v) { return figures.Code(v).error; }, kVelocityQuadratureTolerance,
      kMaxVelocityQuadratureIntervals, &rule, kInitialVelocityQuadratureIntervals);
  a->restoration_error = e.value;
  a->quadrature_evaluations = e.evaluations;
  a->quadrature_intervals = e.intervals;
  a->quadrature_error_estimate = e.error_estimate;
  a->quadrature_converged = e.converged;
  if (discrete) {
    for (const VelocityPoint& p : d.points) {
      a->invertible = a->invertible && figures.Code(p.velocity).invertible;
    }
  }
  // M averaged with the final rule of E's quadrature (for the inverse filter E = V M).
  double m = 0.0;
  for (const VelocityNode& node : rule) m += node.weight * figures.InverseM(node.velocity);
  a->m = a->invertible ? m : kInfinity;
}

}  // namespace

// E_bar = E_V[E(V)] (docs/method.md §13), SNR_100 = 100 / sqrt(E_bar); the snapshot's alike; the
// bound averages the Cauchy-Schwarz bound of Q M, B(v): every code has E(v) >= (10^4 / snr^2)
// f B(v) (f = 1 + c / dt numerical, 1 analog), so E_bar >= (10^4 / snr^2) f E_V[B(V)].
CodeAnalysis analyze_code(const ShutterCode& code, const VelocityDistribution& velocities,
                          double dt, double snr, ShutterMode mode, int grid,
                          const SensorModel& sensor, const RestorationOptions& restoration) {
  std::string error;
  if (!design_detail::design_distribution_is_valid(velocities, dt, &error)) {
    throw_usage_error(error);
  }
  if (velocities.is_point()) {
    return point_analysis(code, velocities, dt, snr, mode, grid, sensor, restoration);
  }
  const double top = design_detail::support_top(velocities);
  design_detail::check_analysis_inputs(code, top, dt, snr, mode, grid, sensor, restoration);
  const std::vector<double>& g = code.gains;
  CodeAnalysis a =
      design_detail::analysis_of_setting(code, top, dt, snr, mode, grid, sensor, restoration);
  a.velocity_distribution = velocities;
  design_detail::describe_gains(g, &a);  // the kernel at the support's largest |v|
  a.q = noise_gain(g, dt, mode);
  design_detail::describe_sensor(g, &a);
  VelocityFigures figures(g, a, velocities.kind == VelocityDistributionKind::kDiscrete);
  average_code_error(velocities, figures, &a);
  a.noise_figure = a.q * a.m;
  a.effective_noise_figure = a.effective_q * a.m;
  a.snr_level100 = 100.0 / std::sqrt(a.restoration_error);  // 0 for an infinite E
  // A continuous support the inverse filter cannot invert: E is infinite from the top down.
  const bool hopeless = std::isinf(a.restoration_error) && !a.invertible &&
                        velocities.kind != VelocityDistributionKind::kDiscrete;
  a.worst_velocity = hopeless ? top : worst_velocity(velocities, figures);
  a.worst_snr_level100 = 100.0 / std::sqrt(figures.Code(a.worst_velocity).error);
  a.regularization = figures.Code(a.worst_velocity).regularization;
  a.snapshot_regularization = figures.Snapshot(a.worst_velocity).regularization;
  const double snapshot_error =
      averaged(velocities, [&figures](double v) { return figures.Snapshot(v).error; });
  a.snapshot_snr_level100 = 100.0 / std::sqrt(snapshot_error);
  a.ratio_to_snapshot =
      a.snapshot_snr_level100 > 0.0 ? a.snr_level100 / a.snapshot_snr_level100 : 0.0;
  const bool inverse = restoration.method == RestorationMethod::kInverse;
  const double readout_factor =
      mode == ShutterMode::kNumerical
          ? 1.0 + readout_noise_slots(sensor, g.size(), dt, mode, snr) / dt
          : 1.0;
  const double bound =
      inverse ? averaged(velocities, [dt](double v) { return noise_figure_lower_bound(v, dt); }) *
                    readout_factor
              : 0.0;
  a.snr_level100_bound = bound == 0.0 ? kInfinity : snr / std::sqrt(bound);
  design_detail::check_analysis_finite(code, a);
  return a;
}

std::string describe_velocity_average(const CodeAnalysis& a) {
  if (!a.velocity_distribution) return "";
  const VelocityDistribution& d = *a.velocity_distribution;
  if (d.is_point()) return "one velocity (the single-velocity figure)";
  if (d.kind == VelocityDistributionKind::kDiscrete) {
    return "the exact weighted sum over its " + std::to_string(d.points.size()) + " velocities";
  }
  if (a.quadrature_evaluations == 0) {
    return "no quadrature (the error is infinite at the support's largest |v|)";
  }
  return "adaptive Gauss-Kronrod quadrature to relative " +
         design_detail::tolerance_text(kVelocityQuadratureTolerance) + " (" +
         std::to_string(a.quadrature_evaluations) + " evaluations, " +
         std::to_string(a.quadrature_intervals) +
         (a.quadrature_intervals == 1 ? " interval" : " intervals") + ", error estimate " +
         format_number(a.quadrature_error_estimate) + " gray levels^2" +
         (a.quadrature_converged
              ? ")"
              : "; the tolerance was not met within " +
                    std::to_string(kMaxVelocityQuadratureIntervals) + " intervals)");
}

}  // namespace fss
