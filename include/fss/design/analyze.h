// Analysing flutter shutter codes without simulating an image: the figure of
// merit of a code, and the Cauchy-Schwarz bound on it over every code.
// Conventions: core/image.h.
//
// Figure of merit (docs/method.md §6). The SNR of the restored image of a
// constant landscape at level 100 is
//   SNR_100 = 100 / sqrt(100 Q (100 / snr^2) M) = snr / sqrt(Q M),
// with Q = dt sum alpha_k^2 (numerical) or dt sum alpha_k (analog) and M the
// mean of 1 / |K(xi)|^2 over the band xi in [-pi, pi]. The product Q M (the
// "noise figure") is the only thing a code changes: SNR_100 is proportional to
// snr, and the ratio of two codes' SNR_100 does not depend on snr at all.
// Scaling a numerical code by c leaves Q M unchanged (Q ~ c^2, M ~ 1 / c^2);
// scaling an analog code by c divides Q M by c.
//
// With a sensor (model/sensor.h, docs/method.md §10) every readout adds
// v_r = sigma_r^2 + d * exposure (+ G^2 / 12 with an ADC) electrons^2 to the
// level-100 observation: the numerical mode reads sum alpha_k^2 weighted
// frames, the analog mode one exposure. In slots of level-100 light this is
//   Q_eff = Q + R c,  c = v_r / (100 lambda2),  lambda2 = snr^2 / 100,
// with R = sum alpha_k^2 (numerical) or 1 (analog), and
//   SNR_100 = snr / sqrt(Q_eff M).
// A frame of gain 0 contributes nothing (its readout is weighted by 0). In
// the numerical mode Q_eff = (1 + c / dt) Q: the sensor lowers every
// numerical code's SNR_100 by the same factor and changes neither their
// ranking nor the numerical optimum. In the analog mode the one readout
// favours codes that let in more light. snr now matters in absolute terms:
// the readout noise counts against lambda2 photo-electrons per gray level.
// A full well is not linear and has no place in this figure of merit.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "fss/model/code.h"
#include "fss/model/sensor.h"

namespace fss {

// Number of midpoint nodes on [0, pi] used to average 1 / |K|^2 over the band
// when no DFT grid is given (|K| is even for real gains, so the half band
// suffices; this is an 8192-node midpoint rule on [-pi, pi]).
inline constexpr int kBandGridPoints = 4096;
// Largest DFT grid analyze_code evaluates M on (each point is a sum over the
// L gains).
inline constexpr int kMaxAnalysisGridPoints = 1 << 16;

// Mean of 1 / |K(xi)|^2 over xi in [-pi, pi] by the midpoint rule with
// `grid_points` nodes on [0, pi]; infinite if K vanishes at a node
// (transfer_vanishes, model/kernel.h).
double band_mean_inverse_power(std::span<const double> gains, double velocity, double dt,
                               int grid_points = kBandGridPoints);

// Cauchy-Schwarz lower bound on Q M for every numerical code of every length
// at this velocity and slot (see README, "Designing codes"):
//   Q M >= (int_{-pi}^{pi} sqrt(w(theta)) d theta)^2 / (4 pi a dt),  a = pi |v| dt,
//   w(theta) = sum over integers m with |theta + 2 pi m| <= a of 1 / sinc_h(theta + 2 pi m)^2.
// For |v| dt = 1 it is (4 G / pi)^2 / dt = 1.36011 / dt (G Catalan's constant).
// It holds for analog codes too (there sum alpha >= sum alpha^2). Infinite for
// |v| dt >= 2, where every code has K = 0 on the band; 0 for v = 0.
double noise_figure_lower_bound(double velocity, double dt);

// c = v_r / (100 lambda2): the variance one readout of this mode adds to the
// level-100 observation, in slots of level-100 light (0 for a default
// sensor). v_r = readout_variance_electrons2 at the mode's exposure
// (readout_exposure_slots: dt per frame, L dt for the analog exposure).
double readout_noise_slots(const SensorModel& sensor, std::size_t length, double dt,
                           ShutterMode mode, double snr);

// Usage error unless the sensor is valid (SensorModel::IsValid) and linear in
// the charge as far as the figure of merit goes: no full well. An ADC is
// counted by its rounding variance G^2 / 12 per readout.
void check_design_sensor(const SensorModel& sensor);

// The parts of `sensor` that are on, in words ("read noise 5 e- RMS per
// readout, dark current 0.5 e- per slot, ADC 12 bits at 2 e- per count");
// "photon noise only" for a default sensor.
std::string describe_design_sensor(const SensorModel& sensor);

struct CodeAnalysis {
  int length = 0;
  ShutterMode mode = ShutterMode::kNumerical;
  double velocity = 1.0;
  double dt = 1.0;
  double snr = 100.0;
  int grid = 0;        // 0: midpoint rule with kBandGridPoints nodes; N > 0: the N-point DFT grid
  SensorModel sensor;  // default: photon noise only (the paper)

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
  // The sensor's part: readouts R (sum alpha_k^2 or 1), v_r per readout in
  // electrons^2, Q_eff = Q + R v_r / (100 lambda2) and Q_eff M; for a
  // default sensor v_r = 0 and Q_eff = Q exactly.
  double readouts = 0.0;
  double readout_variance_electrons2 = 0.0;
  double effective_q = 0.0;
  double effective_noise_figure = 0.0;
  double snr_level100 = 0.0;           // snr / sqrt(Q_eff M); 0 when not invertible
  double snapshot_snr_level100 = 0.0;  // the snapshot (1, 0, ..., 0) of length L, same setting
  double ratio_to_snapshot = 0.0;      // snr_level100 / snapshot_snr_level100
  // snr / sqrt(B (1 + c / dt)) with B = noise_figure_lower_bound(v, dt) in the
  // numerical mode (every numerical code has Q_eff M = (1 + c / dt) Q M); in
  // the analog mode snr / sqrt(B), still a bound (Q_eff M >= Q M >= B).
  double snr_level100_bound = 0.0;
};

// Analyses `code` at the given velocity, slot, snr and mode; `grid` as in
// CodeAnalysis (pass the simulator's mirror width 2 Wa to get exactly its M).
// Throws a usage fss::Error naming the code when the mode cannot use it (as
// fss::check_code_for_mode: no gains, only zero gains, analog gains outside
// [0, 1]), and for a non-finite velocity, dt <= 0, snr <= 0, grid < 0 or a
// sensor check_design_sensor refuses.
CodeAnalysis analyze_code(const ShutterCode& code, double velocity, double dt, double snr,
                          ShutterMode mode, int grid = 0, const SensorModel& sensor = {});

}  // namespace fss
