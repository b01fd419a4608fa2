// Optimizing flutter shutter codes: the code of a given length that maximizes the SNR at level
// 100 (design/analyze.h) at a velocity or averaged over a distribution of velocities, under the
// constraints of the mode, for the inverse filter or a Wiener or Tikhonov restoration.
// Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fss/design/analyze.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"
#include "fss/model/velocity_distribution.h"

namespace fss {

// Longest code optimize_code accepts (its band basis holds 2 x grid x L doubles).
inline constexpr int kMaxOptimizedCodeLength = kMaxCodeLength;
// Bounds of the search's effort: restarts, iterations per start and the objective's grid (a start
// costs about iterations x grid x L).
inline constexpr int kMaxRestarts = 10000;
inline constexpr int kMaxIterations = 100000;
inline constexpr int kMaxObjectiveGridPoints = 1 << 16;

// The optimizer's objective: Q_eff M of a code of fixed length on a midpoint band grid of
// grid_points nodes, with its gradient. Q_eff = Q + R c (docs/method.md §10), c = readout_slots
// the readout noise in slots of level-100 light (readout_noise_slots; 0: photon noise only).
// Throws a usage fss::Error for length < 1, grid_points < 1 or a negative or non-finite c.
class NoiseFigure {
 public:
  NoiseFigure(int length, double velocity, double dt, ShutterMode mode,
              int grid_points = kBandGridPoints, double readout_slots = 0.0);

  int length() const { return length_; }

  // Q_eff M of `gains` (length() values); +infinity when K vanishes at a node or Q_eff <= 0. A
  // non-empty `gradient` (length() values) receives d(Q_eff M) / d alpha, unspecified for an
  // infinite value. Other sizes are a usage fss::Error.
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
  // A distribution of velocities instead (docs/method.md §13); velocity_px_per_slot then stays at
  // its default 1. The criterion is averaged over the velocity nodes of composite_gauss_nodes
  // (kDesignVelocityPanels panels of kDesignVelocityOrder Gauss nodes; a discrete distribution's
  // own velocities), each restored at itself: |v| dt < 2 over the support, and a point
  // distribution 0 < |v| dt < 2 (it gives the single-velocity search at its velocity, bit for
  // bit). The objective holds a band basis of 2 x grid_points x length doubles per node, twice
  // for a binary search under a restoration: at most 1 GiB in all.
  std::optional<VelocityDistribution> velocity_distribution;
  double dt = 1.0;  // > 0
  // > 0; lambda2 = snr^2 / 100 photo-electrons per gray level per slot. It scales the reported
  // SNR only, unless the sensor adds readout noise, which counts against lambda2.
  double snr = 100.0;
  ShutterMode mode = ShutterMode::kNumerical;
  // Read noise, dark current and ADC of the figure of merit (design/analyze.h; default: photon
  // noise only). No full well (check_design_sensor).
  SensorModel sensor;
  // The criterion (design/analyze.h, level100_restoration_error): the inverse filter's Q_eff M
  // (the paper's, the default), or E under a Wiener restoration with a power-law prior or a
  // Tikhonov one (a given lambda, or each code's optimal lambda). No oracle prior
  // (check_design_restoration).
  RestorationOptions restoration;
  // Gains in {0, 1} (Agrawal-Raskar's search space); then Q is the same in both modes.
  bool binary = false;
  // Light budget of analog or binary codes: sum alpha_k >= min_light_slots, in slots of full
  // light (the snapshot lets in 1, Agrawal-Raskar's code 26). 0: no constraint; at most length.
  double min_light_slots = 0.0;
  // Random starting codes, seeded by `seed`, besides the snapshot, (numerical gains) the sinc
  // code and (Wiener, Tikhonov) the best box code.
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
  // The best code found, numerical codes scaled to max |alpha| = 1, analog ones to max alpha = 1
  // (binary codes as found).
  std::vector<double> gains;
  // Of `gains`, at the options' v (or averaged over their distribution: analyze_code's second
  // form), dt, snr, mode, default grid.
  CodeAnalysis analysis;
  int starts = 0;       // starting codes tried
  int best_start = 0;   // index of the start that gave the best code (0: snapshot)
  int iterations = 0;   // iterations or moves over all starts
  int evaluations = 0;  // objective evaluations over all starts

  // Human-readable summary.
  std::string FullReport() const;
};

// Minimizes Q_eff M (the inverse filter) or E (a Wiener or Tikhonov restoration; for Tikhonov
// without a lambda, E at each code's optimal lambda, whose gradient is the partial one at that
// lambda), i.e. maximizes SNR_100 with the sensor's readouts; under a velocity distribution the
// weighted sum sum_i w_i C(v_i) of the criterion C over the velocity nodes (v_i, w_i), with
// gradient sum_i w_i grad C(v_i). Under the constraints of the mode:
// any real gains (numerical), gains in [0, 1] (analog), gains in {0, 1} (binary), and sum alpha
// >= min_light_slots. Under a Wiener or Tikhonov restoration the box code of n ones (n from the
// light budget to L) with the lowest E is a start too, so the result is never worse than it.
// The sinc start is designed for the velocity (a distribution: its support's largest |v|); under
// a distribution the same search at its mean speed E|V| runs first and its optimum is a start,
// so the result is no worse than it under the objective.
// Bounded by iterations, not time: the result depends only on the options. Throws a usage
// fss::Error when the options are not valid.
OptimizationResult optimize_code(const OptimizeOptions& options);

}  // namespace fss
