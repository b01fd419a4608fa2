// Optimizing flutter shutter codes: the code of a given length that maximizes
// the SNR at level 100 (design/analyze.h) at a velocity, under the constraints
// of the mode. Conventions: core/image.h.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fss/design/analyze.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"

namespace fss {

// Longest code optimize_code accepts (the band basis holds 2 G L doubles).
inline constexpr int kMaxOptimizedCodeLength = kMaxCodeLength;
// Bounds of the search's effort: restarts and iterations per start, and the
// objective's grid (each start costs about iterations x grid x L).
inline constexpr int kMaxRestarts = 10000;
inline constexpr int kMaxIterations = 100000;
inline constexpr int kMaxObjectiveGridPoints = 1 << 16;

// Q_eff M of a code of fixed length on a midpoint band grid, with its
// gradient; Q_eff = Q + R c with the readout noise c in slots of level-100
// light (readout_noise_slots, design/analyze.h; 0: photon noise only, Q_eff
// = Q): numerical Q_eff = (dt + c) sum alpha_k^2, analog dt sum alpha_k + c.
// K is linear in alpha, K(xi_j) = sum_k alpha_k E_jk with
// E_jk = dt sinc_h(theta_j) exp(-i theta_j (k + 1/2)), so
//   dM / d alpha_k = -(2 / G) sum_j Re(conj(K_j) E_jk) / |K_j|^4,
//   dQ_eff / d alpha_k = 2 (dt + c) alpha_k (numerical) or dt (analog).
class NoiseFigure {
 public:
  NoiseFigure(int length, double velocity, double dt, ShutterMode mode,
              int grid_points = kBandGridPoints, double readout_slots = 0.0);

  int length() const { return length_; }

  // Q_eff M of `gains` (length() values); +infinity when K vanishes at a
  // node (fss::transfer_vanishes, model/kernel.h) or Q_eff <= 0. When `gradient` is not empty
  // (length() values) it receives d(Q_eff M) / d alpha (left unspecified for an infinite value).
  double Evaluate(std::span<const double> gains, std::span<double> gradient = {}) const;

 private:
  int length_;
  int grid_;
  double dt_;
  double readout_slots_;  // c
  ShutterMode mode_;
  std::vector<double> basis_re_;  // E_jk, row k holds the grid_ nodes j
  std::vector<double> basis_im_;
};

struct OptimizeOptions {
  int length = 52;                    // 1 <= L <= kMaxOptimizedCodeLength
  double velocity_px_per_slot = 1.0;  // 0 < |v| dt < 2
  double dt = 1.0;                    // > 0
  // > 0; photo-electrons per gray level per slot lambda2 = snr^2 / 100. It
  // scales the reported SNR only, unless the sensor adds readout noise, which
  // counts against lambda2.
  double snr = 100.0;
  ShutterMode mode = ShutterMode::kNumerical;
  // Read noise, dark current and ADC of the figure of merit (design/analyze.h;
  // default: photon noise only). No full well (check_design_sensor).
  SensorModel sensor;
  // Gains in {0, 1} (Agrawal-Raskar's search space); then Q is the same in
  // both modes.
  bool binary = false;
  // Light budget: analog or binary codes must let in at least this much light,
  // sum alpha_k >= min_light_slots (in slots of full light; the snapshot lets
  // in 1, Agrawal-Raskar's code 26). 0 means no constraint; at most length.
  double min_light_slots = 0.0;
  // Random starting codes, besides the deterministic ones (the snapshot, and
  // the sinc code for numerical gains). Seeded by `seed`.
  int restarts = 24;
  std::uint64_t seed = 0;
  // Per start: quasi-Newton iterations (continuous gains) or moves (binary).
  int max_iterations = 300;
  // Midpoint nodes on [0, pi] of the objective's band grid.
  int grid_points = 2048;

  // False, with a message naming the field, its value and the rule.
  bool IsValid(std::string* error) const;
};

struct OptimizationResult {
  OptimizeOptions options;
  // The best code found: numerical codes are scaled to max |alpha| = 1
  // (which changes nothing), analog ones to max alpha = 1 (which can only help).
  std::vector<double> gains;
  CodeAnalysis analysis;  // of `gains`, at the options' v, dt, snr, mode, default grid
  int starts = 0;         // starting codes tried
  int best_start = 0;     // index of the start that gave the best code (0: snapshot)
  int iterations = 0;     // iterations or moves over all starts
  int evaluations = 0;    // objective evaluations over all starts

  // Human-readable summary.
  std::string FullReport() const;
};

// Minimizes Q_eff M, i.e. maximizes SNR_100 (with the sensor's readouts),
// under the constraints of the mode:
// any real gains (numerical), gains in [0, 1] (analog), gains in {0, 1}
// (binary), and sum alpha >= min_light_slots. Continuous gains: projected
// L-BFGS on log(Q M) from each start. Binary gains: steepest-descent local
// search over single bit flips, and swaps of a 1 with a 0 when no flip helps,
// from each start. The run is bounded by iterations, not time, and depends
// only on the options. Throws a usage fss::Error when the options are not
// valid.
OptimizationResult optimize_code(const OptimizeOptions& options);

}  // namespace fss
