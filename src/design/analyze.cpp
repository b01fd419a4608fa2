#include "fss/design/analyze.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/scaled_math.h"
#include "design/analysis_parts.h"
#include "design/numerics.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/simulate.h"

namespace fss {

using design_detail::inverse_sinc_h;
using design_detail::kInfinity;
using design_detail::simpson;

namespace design_detail {

// The code is checked by fss::check_code_for_mode (the simulator's check);
// the setting here.
void check_analysis_setting(double velocity, double dt, double snr, int grid) {
  if (!std::isfinite(velocity)) {
    throw_usage_error("velocity " + format_exact(velocity) + " must be a finite number");
  }
  if (!(std::isfinite(dt) && dt > 0.0)) {
    throw_usage_error("dt " + format_exact(dt) + " must be finite and > 0");
  }
  if (!(std::isfinite(snr) && snr > 0.0)) {
    throw_usage_error("snr " + format_exact(snr) + " must be finite and > 0");
  }
  if (grid < 0 || grid > kMaxAnalysisGridPoints) {
    throw_usage_error("grid " + std::to_string(grid) + " must lie in [0, " +
                      std::to_string(kMaxAnalysisGridPoints) + "]");
  }
}

void check_analysis_inputs(const ShutterCode& code, double velocity, double dt, double snr,
                           ShutterMode mode, int grid, const SensorModel& sensor,
                           const RestorationOptions& restoration) {
  check_code_for_mode(code, mode);
  check_analysis_setting(velocity, dt, snr, grid);
  check_design_sensor(sensor);
  check_design_restoration(restoration);
  if (grid != 0 && restoration.method != RestorationMethod::kInverse) {
    throw_usage_error("grid " + std::to_string(grid) +
                      ": the DFT grid is the inverse filter's; the " +
                      to_string(restoration.method) + " figure uses the midpoint rule");
  }
}

double mean_inverse_on_grid(std::span<const double> gains, double velocity, const CodeAnalysis& a) {
  return a.grid == 0 ? band_mean_inverse_power(gains, velocity, a.dt)
                     : mean_inverse_power(gains, velocity, a.dt, a.grid);
}

void describe_gains(const std::vector<double>& g, CodeAnalysis* a) {
  a->sum = gain_sum(g);
  a->square_sum = gain_square_sum(g);
  a->normalized_l1 = normalized_l1(g);
  const KernelAnalysis kernel = analyze_kernel(g, a->velocity, a->dt);
  a->k0 = kernel.k0;
  a->min_abs = kernel.min_abs;
  a->min_abs_xi = kernel.min_abs_xi;
  a->invertible = kernel.invertible;
}

// snr_level100(Q_eff, M, snr) = 100 / sqrt(V M); to the bit the photon noise's Q for a default
// sensor, as before sensors existed.
double effective_noise_gain(std::span<const double> gains, double dt, ShutterMode mode, double snr,
                            const SensorModel& sensor) {
  if (!sensor.enabled()) return noise_gain(gains, dt, mode);
  const double q = level100_observation_variance(gains, dt, mode, snr, sensor) * snr * snr / 1.0e4;
  if (detail::is_normal_positive(q)) return q;
  // V or V snr^2 out of the range of doubles: the same as
  //   numerical: dt sum alpha^2 + sum alpha^2 v_r / snr^2
  //   analog:    dt sum alpha + v_r / snr^2
  // (v_r / (100 lambda2) = v_r / snr^2), with the readouts' term scaled
  // before the division.
  const bool analog = mode == ShutterMode::kAnalog;
  double sum = 0.0;
  for (const double alpha : gains) sum += analog ? alpha : alpha * alpha;
  const double v_r =
      readout_variance_electrons2(sensor, readout_exposure_slots(gains.size(), dt, mode));
  return dt * sum + (analog ? v_r : sum * v_r) / snr / snr;
}

void describe_sensor(std::span<const double> g, CodeAnalysis* a) {
  a->readouts = a->mode == ShutterMode::kNumerical ? a->square_sum : 1.0;
  a->readout_variance_electrons2 =
      readout_variance_electrons2(a->sensor, readout_exposure_slots(g.size(), a->dt, a->mode));
  a->effective_q = effective_noise_gain(g, a->dt, a->mode, a->snr, a->sensor);
  a->effective_noise_figure = a->effective_q * a->m;
}

}  // namespace design_detail

namespace {

using design_detail::analysis_of_setting;
using design_detail::check_analysis_finite;
using design_detail::describe_gains;
using design_detail::describe_sensor;
using design_detail::effective_noise_gain;
using design_detail::error_of_level100_snr;
using design_detail::mean_inverse_on_grid;

// snr_level100 and the snapshot's under a Wiener or Tikhonov restoration: 100 / sqrt(E), E of the
// code and of the snapshot (1, 0, ..., 0) of the same length (level100_restoration_error).
void apply_restoration_figure(std::span<const double> g, CodeAnalysis* a) {
  const RestorationError code =
      level100_restoration_error(g, a->velocity, a->dt, a->snr, a->mode, a->restoration, a->sensor);
  std::vector<double> snapshot(g.size(), 0.0);
  snapshot[0] = 1.0;
  const RestorationError reference = level100_restoration_error(
      snapshot, a->velocity, a->dt, a->snr, a->mode, a->restoration, a->sensor);
  a->restoration_error = code.error;
  a->regularization = code.regularization;
  a->snapshot_regularization = reference.regularization;
  a->snr_level100 = 100.0 / std::sqrt(code.error);
  a->snapshot_snr_level100 = 100.0 / std::sqrt(reference.error);
}

}  // namespace

// Every figure of `a` finite (M, Q M and Q_eff M too when K has no zero), else the setting left
// double precision: a usage error naming code, dt, snr and the sensor's parts that are on.
void design_detail::check_analysis_finite(const ShutterCode& code, const CodeAnalysis& a) {
  bool finite = true;
  for (const double value : {a.sum, a.square_sum, a.normalized_l1, a.k0, a.min_abs, a.q, a.readouts,
                             a.readout_variance_electrons2, a.effective_q, a.snr_level100,
                             a.snapshot_snr_level100, a.ratio_to_snapshot}) {
    finite = finite && std::isfinite(value);
  }
  if (a.invertible) {
    finite = finite && std::isfinite(a.m) && a.m > 0.0 && std::isfinite(a.noise_figure) &&
             a.noise_figure > 0.0 && std::isfinite(a.effective_noise_figure) &&
             a.snr_level100 > 0.0;
  }
  // A Wiener or Tikhonov E is finite for every code but one of zero sum, K(0) = 0, whose E is
  // infinite (level100_restoration_error) and its SNR at level 100 then 0.
  if (a.restoration.method != RestorationMethod::kInverse) {
    const bool lost_mean = std::isinf(a.restoration_error) && a.restoration_error > 0.0 &&
                           transfer_vanishes(std::abs(a.k0), transfer_scale(code.gains, a.dt));
    finite = finite &&
             (lost_mean || (std::isfinite(a.restoration_error) && a.restoration_error > 0.0 &&
                            a.snr_level100 > 0.0)) &&
             a.snapshot_snr_level100 > 0.0 && std::isfinite(a.regularization) &&
             std::isfinite(a.snapshot_regularization);
  }
  if (!finite) {
    const std::string setting =
        "dt " + format_exact(a.dt) +
        (a.sensor.enabled() ? ", snr " + format_exact(a.snr) + " and the sensor (" +
                                  describe_design_sensor(a.sensor) + ")"
                            : " and snr " + format_exact(a.snr));
    throw_usage_error("the analysis of code '" + escape_control_characters(code.name) +
                      "' left the range of double-precision numbers: its gains (|gain| up to " +
                      format_exact(gain_max_abs(code.gains)) + "), " + setting +
                      " are too extreme together");
  }
}

double readout_noise_slots(const SensorModel& sensor, std::size_t length, double dt,
                           ShutterMode mode, double snr) {
  const double lambda2 = snr * snr / 100.0;
  // c = v_r / (100 lambda2)
  return readout_variance_electrons2(sensor, readout_exposure_slots(length, dt, mode)) /
         (100.0 * lambda2);
}

void check_design_sensor(const SensorModel& sensor) {
  std::string error;
  if (!sensor.IsValid(&error)) throw_usage_error(error);
  if (sensor.full_well_electrons) {
    throw_usage_error("full_well_electrons = " + format_number(*sensor.full_well_electrons) +
                      ": the figure of merit of a code is linear in the charge and has no full "
                      "well (simulate the camera to see saturation)");
  }
}

std::string describe_design_sensor(const SensorModel& sensor) {
  std::string text;
  auto add = [&text](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
  if (sensor.read_noise_electrons != 0.0) {
    add("read noise " + format_number(sensor.read_noise_electrons) + " e- RMS per readout");
  }
  if (sensor.dark_current_electrons_per_slot != 0.0) {
    add("dark current " + format_number(sensor.dark_current_electrons_per_slot) + " e- per slot");
  }
  if (sensor.full_well_electrons) {
    add("full well " + format_number(*sensor.full_well_electrons) + " e-");
  }
  if (sensor.adc_bits != 0) {
    add("ADC " + std::to_string(sensor.adc_bits) + " bits at " +
        format_number(sensor.adc_gain_electrons_per_count) + " e- per count");
  }
  return text.empty() ? "photon noise only" : text;
}

double band_mean_inverse_power(std::span<const double> gains, double velocity, double dt,
                               int grid_points) {
  if (grid_points < 1) {
    throw_usage_error("band grid needs at least 1 node, got " + std::to_string(grid_points));
  }
  const double scale = transfer_scale(gains, dt);
  double sum = 0.0;
  for (int j = 0; j < grid_points; ++j) {
    const double xi = (j + 0.5) * M_PI / grid_points;
    const Complex k = transfer_function(gains, velocity, dt, xi);
    if (transfer_vanishes(std::abs(k), scale)) return kInfinity;
    sum += 1.0 / std::norm(k);
  }
  return sum / grid_points;
}

// docs/method.md §11: Q M >= (int_{-pi}^{pi} sqrt(w(theta)) d theta)^2 / (4 pi a dt),
// a = pi |v| dt, w(theta) = sum over integers m with |theta + 2 pi m| <= a of
// 1 / sinc_h(theta + 2 pi m)^2. It holds for analog codes too (there sum alpha >= sum alpha^2).
double noise_figure_lower_bound(double velocity, double dt) {
  const double product = std::abs(velocity) * dt;
  if (product == 0.0) return 0.0;
  if (!(product < 2.0)) return kInfinity;
  const double a = M_PI * product;
  // int_{-pi}^{pi} sqrt(w) = 2 int_0^pi sqrt(w). On [0, pi] the images
  // theta + 2 pi m inside [-a, a] are theta itself (up to a) and, when a > pi,
  // theta - 2 pi for theta >= 2 pi - a.
  constexpr int kIntervals = 20000;
  double half = 0.0;
  if (a <= M_PI) {
    half = simpson(inverse_sinc_h, 0.0, a, kIntervals);
  } else {
    half =
        simpson(inverse_sinc_h, 0.0, 2.0 * M_PI - a, kIntervals) +
        simpson(
            [](double t) { return std::hypot(inverse_sinc_h(t), inverse_sinc_h(2.0 * M_PI - t)); },
            2.0 * M_PI - a, M_PI, kIntervals);
  }
  const double integral = 2.0 * half;
  return integral * integral / (4.0 * M_PI * a * dt);
}

// The figure of merit (docs/method.md §6): SNR_100 = snr / sqrt(Q M). The product Q M (the
// "noise figure") is the only thing a code changes, so the ratio of two codes' SNR_100 does not
// depend on snr. Scaling a numerical code by c leaves Q M unchanged (Q ~ c^2, M ~ 1 / c^2);
// scaling an analog code by c divides Q M by c. With a sensor (§10) every readout adds v_r
// electrons^2 to the level-100 observation: Q_eff = Q + R c, c = v_r / (100 lambda2), R =
// sum alpha_k^2 (numerical: weighted frames; a frame of gain 0 adds nothing) or 1 (analog: one
// exposure), and SNR_100 = snr / sqrt(Q_eff M). In the numerical mode Q_eff = (1 + c / dt) Q
// lowers every code's SNR_100 by the same factor, changing neither their ranking nor the
// optimum; in the analog mode the one readout favours codes that let in more light. snr then
// matters in absolute terms: the readout noise counts against lambda2 photo-electrons per gray
// level. A full well is not linear and has no place in this figure of merit.
// Under a Wiener or Tikhonov restoration (§12) the figure is 100 / sqrt(E) instead
// (level100_restoration_error), for the code and for the snapshot, and the Cauchy-Schwarz bound,
// the inverse filter's, is not given.
CodeAnalysis analyze_code(const ShutterCode& code, double velocity, double dt, double snr,
                          ShutterMode mode, int grid, const SensorModel& sensor,
                          const RestorationOptions& restoration) {
  design_detail::check_analysis_inputs(code, velocity, dt, snr, mode, grid, sensor, restoration);
  const bool inverse = restoration.method == RestorationMethod::kInverse;
  const std::vector<double>& g = code.gains;
  CodeAnalysis a = analysis_of_setting(code, velocity, dt, snr, mode, grid, sensor, restoration);
  describe_gains(g, &a);

  a.q = noise_gain(g, dt, mode);
  // As in the simulator's prediction: a code with a zero on the band has no
  // finite M, whatever the grid happens to sample.
  a.m = a.invertible ? mean_inverse_on_grid(g, velocity, a) : kInfinity;
  a.noise_figure = a.q * a.m;
  describe_sensor(g, &a);
  a.snr_level100 = snr_level100(a.effective_q, a.m, snr);
  // The snapshot's M does not depend on its length; its readouts do (the
  // analog exposure is L dt whatever the gains).
  std::vector<double> snapshot(g.size(), 0.0);
  snapshot[0] = 1.0;
  const double snapshot_q = effective_noise_gain(snapshot, dt, mode, snr, sensor);
  a.snapshot_snr_level100 =
      snr_level100(snapshot_q, mean_inverse_on_grid(std::vector<double>{1.0}, velocity, a), snr);
  a.restoration_error = error_of_level100_snr(a.snr_level100);
  if (!inverse) apply_restoration_figure(g, &a);
  a.ratio_to_snapshot =
      a.snapshot_snr_level100 > 0.0 ? a.snr_level100 / a.snapshot_snr_level100 : 0.0;
  // Numerical: Q_eff M = (1 + c / dt) Q M >= (1 + c / dt) B. Analog: Q_eff M >= Q M >= B.
  const double readout_factor =
      mode == ShutterMode::kNumerical
          ? 1.0 + readout_noise_slots(sensor, g.size(), dt, mode, snr) / dt
          : 1.0;
  const double bound = noise_figure_lower_bound(velocity, dt) * readout_factor;
  a.snr_level100_bound = bound == 0.0 || !inverse ? kInfinity : snr / std::sqrt(bound);
  check_analysis_finite(code, a);
  return a;
}

// The mean charge of a level-100 readout against the ADC's top (adc_range_warning in analyze.h).
std::string adc_range_warning(const CodeAnalysis& a) {
  if (a.sensor.adc_bits == 0) return {};
  const double lambda2 = a.snr * a.snr / 100.0;
  const double exposure = readout_exposure_slots(static_cast<std::size_t>(a.length), a.dt, a.mode);
  // A frame sees one slot of light, the analog exposure sum alpha slots.
  const double light = a.mode == ShutterMode::kNumerical ? a.dt : a.dt * a.sum;
  const double charge =
      100.0 * light * lambda2 + a.sensor.dark_current_electrons_per_slot * exposure;
  const double top =
      (std::ldexp(1.0, a.sensor.adc_bits) - 1.0) * a.sensor.adc_gain_electrons_per_count;
  if (!(charge > top)) return {};
  return "a level-100 readout of " + format_number(charge) + " e- passes the ADC's top of " +
         format_number(top) + " e-: the figure of merit counts its rounding, not its clipping";
}

}  // namespace fss
