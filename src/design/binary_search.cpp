// Steepest-descent local search for binary gains (design/local_search.h).
#include <cmath>
#include <utility>

#include "design/local_search.h"
#include "design/restoration_figure.h"

namespace fss::design_detail {

namespace {

// A move lowers the cost when it does so by more than this relative amount.
constexpr double kRelativeGain = 1e-12;

class BinarySearch {
 public:
  BinarySearch(int length, std::span<const VelocityNode> velocities, double dt, int grid,
               int min_ones, const BinaryCost& cost)
      : length_(length),
        dt_(dt),
        cost_(cost),
        grid_(grid),
        min_ones_(min_ones),
        g_(static_cast<std::size_t>(grid)),
        power_(cost.restoration != nullptr ? g_ : 0, 0.0) {
    for (const VelocityNode& node : velocities) {
      Band band;
      band.weight = node.weight;
      band.re.assign(g_, 0.0);
      band.im.assign(g_, 0.0);
      make_band_basis(length, node.velocity, dt, grid, &band.basis_re, &band.basis_im);
      bands_.push_back(std::move(band));
    }
  }

  LocalResult Run(std::vector<double> x, int max_moves);

 private:
  // The best move: a flip of gain a (b = -1) or a swap of a 1 at a with a 0
  // at b, and the cost after it.
  struct Move {
    int a = -1;
    int b = -1;
    double value = kInfinity;
  };
  // One velocity node: its weight, its basis E_jk and K of the current code on the grid.
  struct Band {
    double weight = 1.0;
    std::vector<double> basis_re, basis_im;
    std::vector<double> re, im;
  };

  void AddRow(int k, double sign);
  double BandValueAfter(const Band& band, int a, double sign_a, int b, double sign_b, double q,
                        int count) const;
  double ValueAfter(int a, double sign_a, int b, double sign_b, int count) const;
  void BestFlip(Move* best);
  void BestSwap(Move* best);
  void Make(const Move& move);

  int length_;
  double dt_;
  BinaryCost cost_;
  int grid_;
  int min_ones_;
  std::size_t g_;
  std::vector<Band> bands_;
  // |K|^2 of a candidate on the grid, under a restoration (ValueAfter is const but reuses it).
  mutable std::vector<double> power_;
  std::vector<double> x_;
  int ones_ = 0;
  LocalResult result_;
};

// K += sign E_k at every node.
void BinarySearch::AddRow(int k, double sign) {
  for (Band& band : bands_) {
    for (std::size_t j = 0; j < g_; ++j) {
      band.re[j] += sign * band.basis_re[k * g_ + j];
      band.im[j] += sign * band.basis_im[k * g_ + j];
    }
  }
}

// At one node: Q_eff M after adding sign_a E_a + sign_b E_b to K (b = -1: no
// second row), M = mean of 1 / |K|^2; under a restoration (cost_.restoration)
// its E instead, with V = (10^4 / snr^2) Q_eff and kappa = dt count.
double BinarySearch::BandValueAfter(const Band& band, int a, double sign_a, int b, double sign_b,
                                    double q, int count) const {
  const double* ar = band.basis_re.data() + a * g_;
  const double* ai = band.basis_im.data() + a * g_;
  const double* br = band.basis_re.data() + (b < 0 ? a : b) * g_;
  const double* bi = band.basis_im.data() + (b < 0 ? a : b) * g_;
  const double weight_b = b < 0 ? 0.0 : sign_b;
  if (cost_.restoration != nullptr) {
    // finite where K vanishes
    for (std::size_t j = 0; j < g_; ++j) {
      const double r = band.re[j] + sign_a * ar[j] + weight_b * br[j];
      const double i = band.im[j] + sign_a * ai[j] + weight_b * bi[j];
      power_[j] = r * r + i * i;
    }
    return cost_.restoration->Evaluate(power_, cost_.noise_per_q * q, dt_ * count).error;
  }
  double sum = 0.0;
  for (std::size_t j = 0; j < g_; ++j) {
    const double r = band.re[j] + sign_a * ar[j] + weight_b * br[j];
    const double i = band.im[j] + sign_a * ai[j] + weight_b * bi[j];
    const double power = r * r + i * i;
    if (!(power > 0.0)) return kInfinity;
    sum += 1.0 / power;
  }
  return q * sum / grid_;
}

// The cost of the code of `count` ones after the move: sum_i w_i C(v_i) over the nodes, C the
// node's Q_eff M or E; Q_eff = dt count without readout noise, with it (dt + c) count
// (numerical) or dt count + c (analog). One node of weight 1 gives its C to the bit.
double BinarySearch::ValueAfter(int a, double sign_a, int b, double sign_b, int count) const {
  if (count == 0 || count < min_ones_) return kInfinity;
  const double q =
      cost_.numerical ? (dt_ + cost_.readout_slots) * count : dt_ * count + cost_.readout_slots;
  double total = 0.0;
  for (const Band& band : bands_) {
    const double value = BandValueAfter(band, a, sign_a, b, sign_b, q, count);
    if (std::isinf(value)) return value;
    total += band.weight * value;
  }
  return total;
}

void BinarySearch::BestFlip(Move* best) {
  for (int k = 0; k < length_; ++k) {
    const double sign = x_[k] == 1.0 ? -1.0 : 1.0;
    const double candidate = ValueAfter(k, sign, -1, 0.0, ones_ + static_cast<int>(sign));
    ++result_.evaluations;
    if (candidate < best->value * (1.0 - kRelativeGain)) *best = {k, -1, candidate};
  }
}

void BinarySearch::BestSwap(Move* best) {
  for (int a = 0; a < length_; ++a) {
    if (x_[a] != 1.0) continue;
    for (int b = 0; b < length_; ++b) {
      if (x_[b] != 0.0) continue;
      const double candidate = ValueAfter(a, -1.0, b, 1.0, ones_);
      ++result_.evaluations;
      if (candidate < best->value * (1.0 - kRelativeGain)) *best = {a, b, candidate};
    }
  }
}

void BinarySearch::Make(const Move& move) {
  const double sign = x_[move.a] == 1.0 ? -1.0 : 1.0;
  AddRow(move.a, sign);
  x_[move.a] = sign > 0.0 ? 1.0 : 0.0;
  ones_ += static_cast<int>(sign);
  if (move.b >= 0) {
    AddRow(move.b, 1.0);
    x_[move.b] = 1.0;
    ++ones_;
  }
}

LocalResult BinarySearch::Run(std::vector<double> x, int max_moves) {
  x_ = std::move(x);
  for (int k = 0; k < length_; ++k) {
    x_[k] = x_[k] > 0.5 ? 1.0 : 0.0;
    if (x_[k] == 1.0) {
      ++ones_;
      AddRow(k, 1.0);
    }
  }
  result_.evaluations = 1;
  double current = ValueAfter(0, 0.0, -1, 0.0, ones_);
  for (int move = 0; move < max_moves; ++move) {
    Move best{-1, -1, current};
    BestFlip(&best);
    if (best.a < 0) BestSwap(&best);
    if (best.a < 0) break;
    Make(best);
    current = best.value;
    ++result_.iterations;
  }
  result_.gains = std::move(x_);
  result_.value = current;
  return result_;
}

}  // namespace

LocalResult minimize_binary(int length, std::span<const VelocityNode> velocities, double dt,
                            int grid, int min_ones, std::vector<double> x, int max_moves,
                            const BinaryCost& cost) {
  BinarySearch search(length, velocities, dt, grid, min_ones, cost);
  return search.Run(std::move(x), max_moves);
}

}  // namespace fss::design_detail
