// Analysing flutter shutter codes without simulating an image: a code's figure of merit, the SNR
// at level 100 (docs/method.md §6, with a sensor §10), and the bound on it over every code (§11).
// Conventions: fss/fss.h.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "fss/model/code.h"
#include "fss/model/sensor.h"

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
  // The sensor's part (docs/method.md §10): readouts R (sum alpha_k^2 or 1), v_r per readout in
  // electrons^2, Q_eff = Q + R v_r / (100 lambda2) and Q_eff M; a default sensor gives Q_eff = Q.
  double readouts = 0.0;
  double readout_variance_electrons2 = 0.0;
  double effective_q = 0.0;
  double effective_noise_figure = 0.0;
  double snr_level100 = 0.0;           // snr / sqrt(Q_eff M); 0 when not invertible
  double snapshot_snr_level100 = 0.0;  // the snapshot (1, 0, ..., 0) of length L, same setting
  double ratio_to_snapshot = 0.0;      // snr_level100 / snapshot_snr_level100
  // Upper bound on snr_level100 over every code (§11), B = noise_figure_lower_bound(v, dt):
  // snr / sqrt(B (1 + c / dt)) in the numerical mode, snr / sqrt(B) in the analog mode.
  double snr_level100_bound = 0.0;
};

// Analyses `code` at the given velocity, slot, snr and mode; `grid` as in CodeAnalysis (the
// simulator's mirror width 2 Wa gives exactly its M). Throws a usage fss::Error naming the code
// when the mode cannot use it (check_code_for_mode), and for a non-finite velocity, dt <= 0,
// snr <= 0, grid outside [0, kMaxAnalysisGridPoints] or a sensor check_design_sensor refuses.
CodeAnalysis analyze_code(const ShutterCode& code, double velocity, double dt, double snr,
                          ShutterMode mode, int grid = 0, const SensorModel& sensor = {});

}  // namespace fss
