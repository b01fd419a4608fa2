// Analysing flutter shutter codes without simulating an image: a code's figure of merit, the SNR
// at level 100 (docs/method.md §6, with a sensor §10), and the bound on it over every code (§11);
// under the inverse filter (the paper's) or a Wiener or Tikhonov restoration (§12); at one
// velocity or averaged over a distribution of velocities (§13).
// Conventions: fss/fss.h.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>

#include "fss/model/code.h"
#include "fss/model/restoration.h"
#include "fss/model/sensor.h"
#include "fss/model/velocity_distribution.h"

namespace fss {

// Midpoint nodes on [0, pi] (|K| is even) of the band average of 1 / |K|^2 when no DFT grid is
// given.
inline constexpr int kBandGridPoints = 4096;
// Largest DFT grid analyze_code evaluates M on.
inline constexpr int kMaxAnalysisGridPoints = 1 << 16;

// Mean of 1 / |K(xi)|^2 over xi in [-pi, pi] by the midpoint rule with
// `grid_points` nodes on [0, pi]; infinite if K vanishes at a node
// (transfer_vanishes, model/kernel.h).
double band_mean_inverse_power(std::span<const double> gains, double velocity, double dt,
                               int grid_points = kBandGridPoints);

// Cauchy-Schwarz lower bound on Q M for every code, numerical or analog, of every length at this
// velocity and slot (docs/method.md §11): (4 G / pi)^2 / dt for |v| dt = 1 (G Catalan's
// constant); infinite for |v| dt >= 2, where no code is invertible; 0 for v = 0.
double noise_figure_lower_bound(double velocity, double dt);

// c = v_r / (100 lambda2): the variance one readout of this mode adds to the level-100
// observation, in slots of level-100 light (0 for a default sensor); v_r =
// readout_variance_electrons2 at readout_exposure_slots(length, dt, mode).
double readout_noise_slots(const SensorModel& sensor, std::size_t length, double dt,
                           ShutterMode mode, double snr);

// Throws a usage fss::Error unless the sensor is valid (SensorModel::IsValid) and has no full
// well; an ADC counts by its rounding variance G^2 / 12 per readout.
void check_design_sensor(const SensorModel& sensor);

// The parts of `sensor` that are on, in words ("read noise 5 e- RMS per
// readout, dark current 0.5 e- per slot, ADC 12 bits at 2 e- per count");
// "photon noise only" for a default sensor.
std::string describe_design_sensor(const SensorModel& sensor);

// Throws a usage fss::Error unless the restoration is valid (RestorationOptions::IsValid) and its
// prior is not the oracle (code design has no image).
void check_design_restoration(const RestorationOptions& restoration);

// The criterion of the figure of merit in words: "wiener restoration, power-law prior gamma 2,
// C 180 (stationary expected error at level 100)", "tikhonov restoration, lambda optimal in
// [1e-08, 100], its bias measured under the default power-law prior gamma 2, C 180 (...)".
std::string describe_design_criterion(const RestorationOptions& restoration);

struct RestorationError {
  double error = 0.0;           // E, gray levels^2
  double regularization = 0.0;  // Tikhonov: the lambda of E (the optimal one if none is given)
};

// E, the stationary expected squared error of the restored image of a landscape at level 100
// (docs/method.md §12), by the midpoint rule with kBandGridPoints nodes on [0, pi] (the
// integrands are even in xi), V the variance of the level-100 observation
// (level100_observation_variance, model/sensor.h: photon noise and readouts):
//   inverse:  E = V M (M = band_mean_inverse_power); infinite for a code that is not
//             invertible (analyze_kernel);
//   wiener:   E = (1/2 pi) int_{-pi}^{pi} V S / (|K|^2 S + V) dxi, S(xi) = C |xi|^-gamma, the
//             power-law prior (C = prior_level, kDefaultPriorLevel when empty);
//   tikhonov: E = (1/2 pi) int [mu^2 S + |K|^2 V] / (|K|^2 + mu)^2 dxi, mu = lambda kappa^2,
//             kappa = dt sum |alpha_k|, S the default power-law prior (gamma 2, C
//             kDefaultPriorLevel), which measures the bias; without a regularization the lambda
//             in [kMinRegularization, kMaxRegularization] minimising E (a grid of 4 nodes a
//             decade in log lambda, then a golden-section search).
// The SNR at level 100 is 100 / sqrt(E). Wiener and Tikhonov give a finite E for a code that is
// not invertible; numerical codes scaled by s keep their E (V and |K|^2 scale by s^2). No mode
// check of the gains (analyze_code makes it). Throws a usage fss::Error for a restoration
// check_design_restoration refuses, a sensor check_design_sensor refuses, no gains, a
// non-finite velocity, dt <= 0 or snr <= 0.
RestorationError level100_restoration_error(std::span<const double> gains, double velocity,
                                            double dt, double snr, ShutterMode mode,
                                            const RestorationOptions& restoration = {},
                                            const SensorModel& sensor = {});

struct CodeAnalysis {
  int length = 0;
  ShutterMode mode = ShutterMode::kNumerical;
  double velocity = 1.0;
  double dt = 1.0;
  double snr = 100.0;
  int grid = 0;        // 0: midpoint rule with kBandGridPoints nodes; N > 0: the N-point DFT grid
  SensorModel sensor;  // default: photon noise only (the paper)
  // The criterion of snr_level100 (default: the inverse filter, the paper's).
  RestorationOptions restoration;

  double sum = 0.0;            // sum alpha_k
  double square_sum = 0.0;     // sum alpha_k^2
  double normalized_l1 = 0.0;  // ||alpha||_1 / sup |alpha|
  double k0 = 0.0;             // K(0) = dt sum alpha_k
  double min_abs = 0.0;        // min |K| on [-pi, pi] (fss::analyze_kernel)
  double min_abs_xi = 0.0;     // where (the non-negative one of a +/- pair)
  bool invertible = false;

  double q = 0.0;             // Q (photon noise)
  double m = 0.0;             // M on the grid; infinite when not invertible
  double noise_figure = 0.0;  // Q M (photon noise)
  // The sensor's part (docs/method.md §10): readouts R (sum alpha_k^2 or 1), v_r per readout in
  // electrons^2, Q_eff = Q + R v_r / (100 lambda2) and Q_eff M; a default sensor gives Q_eff = Q.
  double readouts = 0.0;
  double readout_variance_electrons2 = 0.0;
  double effective_q = 0.0;
  double effective_noise_figure = 0.0;
  // E under the restoration (level100_restoration_error), gray levels^2: the inverse filter's
  // V M, infinite when not invertible.
  double restoration_error = 0.0;
  // Tikhonov: the lambda of the code's E and of the snapshot's (each its own optimal lambda when
  // the restoration gives none); 0 otherwise.
  double regularization = 0.0;
  double snapshot_regularization = 0.0;
  // 100 / sqrt(E): snr / sqrt(Q_eff M) for the inverse filter, 0 when not invertible.
  double snr_level100 = 0.0;
  double snapshot_snr_level100 = 0.0;  // the snapshot (1, 0, ..., 0) of length L, same criterion
  double ratio_to_snapshot = 0.0;      // snr_level100 / snapshot_snr_level100
  // Upper bound on snr_level100 over every code (§11), B = noise_figure_lower_bound(v, dt):
  // snr / sqrt(B (1 + c / dt)) in the numerical mode, snr / sqrt(B) in the analog mode. The
  // bound is the inverse filter's: infinite (none) under a Wiener or Tikhonov restoration.
  double snr_level100_bound = 0.0;

  // Under a velocity distribution (analyze_code's second form; docs/method.md §13): the
  // distribution, and the figures above averaged over it. restoration_error is E_bar =
  // E_V[E(V)], each velocity restored at itself (Tikhonov without a lambda: each velocity's
  // optimal lambda), snr_level100 = 100 / sqrt(E_bar), the snapshot's alike, m = E_V[M(V)] (with
  // the final rule of E_bar's quadrature), noise_figure = Q m, effective_noise_figure = Q_eff m;
  // snr_level100_bound = snr / sqrt(E_V[B(V)] f), B the Cauchy-Schwarz bound of Q M and f its
  // readout factor. velocity, min_abs, min_abs_xi and k0 are the kernel's at the support's
  // velocity of largest |v|; invertible is true when the code is invertible at every velocity of
  // the support. regularization and snapshot_regularization (Tikhonov) are the lambdas at
  // worst_velocity. Without a distribution these keep their defaults.
  std::optional<VelocityDistribution> velocity_distribution;
  double worst_velocity = 0.0;      // the velocity of the support with the largest E(v)
  double worst_snr_level100 = 0.0;  // 100 / sqrt(E(worst_velocity)); 0 where E is infinite
  // E_bar's quadrature (expected_over_velocity, relative tolerance kVelocityQuadratureTolerance):
  // f evaluations, final intervals (0 for a discrete distribution: the exact sum), the summed
  // error estimate (gray levels^2) and whether it met the tolerance within
  // kMaxVelocityQuadratureIntervals intervals. A point distribution: 1, 0, 0, true.
  int quadrature_evaluations = 0;
  int quadrature_intervals = 0;
  double quadrature_error_estimate = 0.0;
  bool quadrature_converged = true;
};

// Analyses `code` at the given velocity, slot, snr and mode; `grid` as in CodeAnalysis (the
// simulator's mirror width 2 Wa gives exactly its M); the figure of merit under `restoration`.
// Throws a usage fss::Error naming the code when the mode cannot use it (check_code_for_mode),
// and for a non-finite velocity, dt <= 0, snr <= 0, grid outside [0, kMaxAnalysisGridPoints], a
// DFT grid with a restoration other than the inverse filter (their figures use the midpoint
// rule), a sensor check_design_sensor refuses or a restoration check_design_restoration refuses.
CodeAnalysis analyze_code(const ShutterCode& code, double velocity, double dt, double snr,
                          ShutterMode mode, int grid = 0, const SensorModel& sensor = {},
                          const RestorationOptions& restoration = {});

// Analyses `code` averaged over a distribution of velocities (docs/method.md §13): E_bar =
// E_V[E(V)] by adaptive Gauss-Kronrod quadrature to kVelocityQuadratureTolerance (a discrete
// distribution: the exact weighted sum), the worst velocity of the support (a scan of 257 evenly
// spaced velocities and the quadrature's nodes, refined by golden-section search; a discrete
// distribution: its points), the snapshot's and the bound's
// averages. Under the inverse filter a code not invertible at the support's largest |v| (at one
// of its velocities, discrete) has an infinite E_bar and SNR 0, worst_velocity that velocity.
// A point distribution gives analyze_code at its velocity bit for bit (and worst_velocity that
// velocity). Throws as analyze_code, and a usage fss::Error naming the distribution when it is
// not valid or its support reaches |v| dt >= 2.
CodeAnalysis analyze_code(const ShutterCode& code, const VelocityDistribution& velocities,
                          double dt, double snr, ShutterMode mode, int grid = 0,
                          const SensorModel& sensor = {},
                          const RestorationOptions& restoration = {});

// With an ADC, the warning that the mean level-100 readout of the analysis (100 dt lambda2
// electrons a frame, 100 dt sum alpha lambda2 the analog exposure, lambda2 = snr^2 / 100, plus the
// dark current over readout_exposure_slots) passes the top of the ADC's range, (2^bits - 1) G:
// "a level-100 readout of 1.2e+06 e- passes the ADC's top of 4095 e-: the figure of merit counts
// its rounding, not its clipping"; "" when it does not or there is no ADC.
std::string adc_range_warning(const CodeAnalysis& analysis);

// How an analysis under a velocity distribution averaged its error, in words: "adaptive
// Gauss-Kronrod quadrature to relative 1e-4 (405 evaluations, 14 intervals, error estimate
// 0.00037 gray levels^2)", "the exact weighted sum over its 7 velocities", "one velocity (the
// single-velocity figure)"; "" without a distribution.
std::string describe_velocity_average(const CodeAnalysis& analysis);

}  // namespace fss
