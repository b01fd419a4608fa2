// The optimizer's local searches from one starting code (design/optimize.h);
// not part of the public interface.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "design/numerics.h"
#include "fss/design/optimize.h"
#include "fss/model/velocity_distribution.h"

namespace fss::design_detail {

struct LocalResult {
  std::vector<double> gains;
  double value = kInfinity;  // Q_eff M, or E under a Wiener or Tikhonov restoration
  int iterations = 0;
  int evaluations = 0;
};

// The band grid of the optimizer: midpoint nodes xi_j = (j + 1/2) pi / G and
// E_jk = dt sinc_h(theta_j) exp(-i theta_j (k + 1/2)), theta_j = xi_j v dt,
// stored row k by row k so that K = sum_k alpha_k E_k is a sum of rows.
void make_band_basis(int length, double velocity, double dt, int grid, std::vector<double>* re,
                     std::vector<double>* im);

// The feasible set of continuous gains: the box [lower, upper]^L (infinite
// bounds for numerical gains), intersected with sum x >= min_sum.
struct Feasible {
  double lower = -kInfinity;
  double upper = kInfinity;
  double min_sum = 0.0;  // 0: no light budget

  // Euclidean projection. Onto the box it is a clamp; when the clamped point
  // misses the budget, the projection is clamp(y + lambda) with the lambda > 0
  // that meets sum = min_sum (KKT), found by bisection (the sum is monotone).
  void Project(std::vector<double>& y) const;
};

// An objective of the continuous search: its value at `gains` (+infinity where it is not
// defined) and, when `gradient` is not empty, its gradient there (NoiseFigure::Evaluate,
// RestorationObjective::Evaluate).
using ContinuousObjective =
    std::function<double(std::span<const double> gains, std::span<double> gradient)>;

// Projected L-BFGS on log(Q M) over a Feasible set, from `x`, for at most
// `max_iterations` iterations. The quasi-Newton direction is computed with the
// gradient restricted to the free variables (those not held at a bound of the
// box by the gradient), and the step is projected back onto the set with a
// backtracking Armijo search along the projection arc; when that fails the
// memory is dropped and the projected gradient is used, which always descends.
// No gains (and an infinite value) when Q M is infinite at the projected start.
LocalResult minimize_continuous(const ContinuousObjective& objective, std::vector<double> x,
                                const Feasible& feasible, int max_iterations);

class BandRestoration;  // design/restoration_figure.h

// The readouts of a binary code: c (readout_noise_slots, design/analyze.h)
// per unit of gain squared (numerical: every 1 is a read frame) or once
// (analog); and the criterion: Q_eff M without `restoration`, else its E
// with V = noise_per_q Q_eff and kappa = dt (number of ones).
struct BinaryCost {
  bool numerical = false;
  double readout_slots = 0.0;  // c; 0: photon noise only
  const BandRestoration* restoration = nullptr;
  double noise_per_q = 0.0;  // 10^4 / snr^2
};

// Steepest-descent local search on binary codes of at least `min_ones` ones,
// from `x`, for at most `max_moves` moves. A move flips one gain or, when no
// flip helps, swaps a 1 with a 0 (which keeps the light, so the search can
// move along a light budget); the move that lowers the cost the most is made,
// until none lowers it. The cost is sum_i w_i C(v_i) over the velocity nodes
// (v_i, w_i) (one node of weight 1 at a single velocity), C(v) the criterion
// of `cost` at v: Q_eff M(v) or E(v). K is updated incrementally at each node
// (K +/- E_k), so one pass over the neighbours costs G operations per
// neighbour and node. Q = dt * (number of ones) in both modes; Q_eff adds the
// readouts of `cost`.
LocalResult minimize_binary(int length, std::span<const VelocityNode> velocities, double dt,
                            int grid, int min_ones, std::vector<double> x, int max_moves,
                            const BinaryCost& cost = {});

}  // namespace fss::design_detail
