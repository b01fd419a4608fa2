// Steepest-descent local search for binary gains (design/local_search.h).
#include <utility>

#include "design/local_search.h"
#include "design/restoration_figure.h"

namespace fss::design_detail {

namespace {

// A move lowers Q M when it does so by more than this relative amount.
constexpr double kRelativeGain = 1e-12;

class BinarySearch {
 public:
  BinarySearch(int length, double velocity, double dt, int grid, int min_ones,
               const BinaryCost& cost)
      : length_(length),
        dt_(dt),
        cost_(cost),
        grid_(grid),
        min_ones_(min_ones),
        g_(static_cast<std::size_t>(grid)),
        re_(g_, 0.0),
        im_(g_, 0.0),
        power_(cost.restoration != nullptr ? g_ : 0, 0.0) {
    make_band_basis(length, velocity, dt, grid, &basis_re_, &basis_im_);
  }

  LocalResult Run(std::vector<double> x, int max_moves);

 private:
  // The best move: a flip of gain a (b = -1) or a swap of a 1 at a with a 0
  // at b, and the Q M after it.
  struct Move {
    int a = -1;
    int b = -1;
    double value = kInfinity;
  };

  void AddRow(int k, double sign);
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
  std::vector<double> basis_re_, basis_im_;
  std::vector<double> re_, im_;  // K of the current code on the grid
  // |K|^2 of a candidate on the grid, under a restoration (ValueAfter is const but reuses it).
  mutable std::vector<double> power_;
  std::vector<double> x_;
  int ones_ = 0;
  LocalResult result_;
};

// K += sign E_k.
void BinarySearch::AddRow(int k, double sign) {
  for (std::size_t j = 0; j < g_; ++j) {
    re_[j] += sign * basis_re_[k * g_ + j];
    im_[j] += sign * basis_im_[k * g_ + j];
  }
}

// Q_eff M after adding sign_a E_a + sign_b E_b to K (b = -1: no second row),
// for a code of `count` ones: M = mean of 1 / |K|^2 and Q_eff = dt count
// without readout noise; with it (dt + c) count (numerical) or dt count + c
// (analog). Under a restoration (cost_.restoration), its E instead.
double BinarySearch::ValueAfter(int a, double sign_a, int b, double sign_b, int count) const {
  if (count == 0 || count < min_ones_) return kInfinity;
  const double* ar = basis_re_.data() + a * g_;
  const double* ai = basis_im_.data() + a * g_;
  const double* br = basis_re_.data() + (b < 0 ? a : b) * g_;
  const double* bi = basis_im_.data() + (b < 0 ? a : b) * g_;
  const double weight_b = b < 0 ? 0.0 : sign_b;
  const double q =
      cost_.numerical ? (dt_ + cost_.readout_slots) * count : dt_ * count + cost_.readout_slots;
  if (cost_.restoration != nullptr) {
    // E with V = (10^4 / snr^2) Q_eff and kappa = dt count; finite where K vanishes.
    for (std::size_t j = 0; j < g_; ++j) {
      const double r = re_[j] + sign_a * ar[j] + weight_b * br[j];
      const double i = im_[j] + sign_a * ai[j] + weight_b * bi[j];
      power_[j] = r * r + i * i;
    }
    return cost_.restoration->Evaluate(power_, cost_.noise_per_q * q, dt_ * count).error;
  }
  double sum = 0.0;
  for (std::size_t j = 0; j < g_; ++j) {
    const double r = re_[j] + sign_a * ar[j] + weight_b * br[j];
    const double i = im_[j] + sign_a * ai[j] + weight_b * bi[j];
    const double power = r * r + i * i;
    if (!(power > 0.0)) return kInfinity;
    sum += 1.0 / power;
  }
  return q * sum / grid_;
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

LocalResult minimize_binary(int length, double velocity, double dt, int grid, int min_ones,
                            std::vector<double> x, int max_moves, const BinaryCost& cost) {
  BinarySearch search(length, velocity, dt, grid, min_ones, cost);
  return search.Run(std::move(x), max_moves);
}

}  // namespace fss::design_detail
