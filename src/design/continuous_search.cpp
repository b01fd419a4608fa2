// Projected L-BFGS on log(Q M) for continuous gains (design/local_search.h).
#include <algorithm>
#include <cmath>
#include <deque>

#include "design/local_search.h"

namespace fss::design_detail {

namespace {

constexpr int kMemory = 8;             // (s, y) pairs kept
constexpr double kArmijo = 1e-4;       // sufficient decrease
constexpr int kMaxBacktracks = 60;     // halvings of the step
constexpr double kStationary = 1e-10;  // max |x - P(x - g)| at a stationary point
constexpr int kMaxStalls = 5;          // iterations in a row lowering log(Q M) by < 1e-13

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// The last kMemory steps s and gradient changes y, with rho = 1 / (s . y).
class LbfgsMemory {
 public:
  bool empty() const { return s_.empty(); }

  void Forget() {
    s_.clear();
    y_.clear();
    rho_.clear();
  }

  // Stores (s, y) when the curvature s . y is positive enough.
  void Remember(std::vector<double> s, std::vector<double> y) {
    const double sy = dot(s, y);
    if (!(sy > 1e-12 * std::sqrt(dot(s, s) * dot(y, y)))) return;
    s_.push_back(std::move(s));
    y_.push_back(std::move(y));
    rho_.push_back(1.0 / sy);
    if (static_cast<int>(s_.size()) > kMemory) {
      s_.pop_front();
      y_.pop_front();
      rho_.pop_front();
    }
  }

  // The two-loop recursion: d becomes H d, H the inverse Hessian estimate
  // (gamma I before the first pair).
  void Apply(std::vector<double>& d) const {
    const std::size_t n = d.size();
    std::vector<double> alphas(s_.size());
    for (std::size_t m = s_.size(); m-- > 0;) {
      alphas[m] = rho_[m] * dot(s_[m], d);
      for (std::size_t i = 0; i < n; ++i) d[i] -= alphas[m] * y_[m][i];
    }
    if (!s_.empty()) {
      const double gamma = dot(s_.back(), y_.back()) / dot(y_.back(), y_.back());
      for (double& v : d) v *= gamma;
    }
    for (std::size_t m = 0; m < s_.size(); ++m) {
      const double beta = rho_[m] * dot(y_[m], d);
      for (std::size_t i = 0; i < n; ++i) d[i] += (alphas[m] - beta) * s_[m][i];
    }
  }

 private:
  std::deque<std::vector<double>> s_, y_;
  std::deque<double> rho_;
};

class ContinuousSearch {
 public:
  ContinuousSearch(const ContinuousObjective& objective, const Feasible& feasible, std::size_t n)
      : objective_(objective),
        feasible_(feasible),
        n_(n),
        g_(n),
        trial_(n),
        trial_g_(n),
        direction_(n),
        is_free_(n) {}

  LocalResult Run(std::vector<double> x, int max_iterations);

 private:
  double Evaluate(const std::vector<double>& v, std::vector<double>& gradient);
  bool IsStationary();
  bool ChooseDirection(double* step);
  bool LineSearch(double step, double* trial_f);

  const ContinuousObjective& objective_;
  const Feasible& feasible_;
  std::size_t n_;
  LocalResult result_;
  std::vector<double> x_, g_, trial_, trial_g_, direction_;
  std::vector<bool> is_free_;
  double f_ = kInfinity;
  LbfgsMemory memory_;
};

// f = log(F), gradient = grad(F) / F, F the objective (Q M, or E); infinite
// where F is not a finite positive number.
double ContinuousSearch::Evaluate(const std::vector<double>& v, std::vector<double>& gradient) {
  ++result_.evaluations;
  const double value = objective_(v, gradient);
  if (!std::isfinite(value) || !(value > 0.0)) return kInfinity;
  for (double& d : gradient) d /= value;
  return std::log(value);
}

// Stationarity: x = P(x - g). Also marks the free variables.
bool ContinuousSearch::IsStationary() {
  for (std::size_t i = 0; i < n_; ++i) trial_[i] = x_[i] - g_[i];
  feasible_.Project(trial_);
  double projected_gradient = 0.0;
  for (std::size_t i = 0; i < n_; ++i) {
    is_free_[i] =
        !((x_[i] <= feasible_.lower && g_[i] > 0.0) || (x_[i] >= feasible_.upper && g_[i] < 0.0));
    projected_gradient = std::max(projected_gradient, std::abs(x_[i] - trial_[i]));
  }
  return projected_gradient < kStationary;
}

// The quasi-Newton direction on the free variables, or steepest descent when
// it does not descend or there is no memory; the first step to try. False
// when no variable is free to move.
bool ContinuousSearch::ChooseDirection(double* step) {
  for (std::size_t i = 0; i < n_; ++i) direction_[i] = is_free_[i] ? g_[i] : 0.0;
  memory_.Apply(direction_);
  double slope = 0.0;
  double largest = 0.0;
  for (std::size_t i = 0; i < n_; ++i) {
    direction_[i] = is_free_[i] ? -direction_[i] : 0.0;
    slope += direction_[i] * g_[i];
    largest = std::max(largest, std::abs(direction_[i]));
  }
  if (!(slope < 0.0) || memory_.empty()) {
    // Steepest descent, with a first step of at most 0.1 per gain.
    memory_.Forget();
    largest = 0.0;
    for (std::size_t i = 0; i < n_; ++i) {
      direction_[i] = is_free_[i] ? -g_[i] : 0.0;
      largest = std::max(largest, std::abs(direction_[i]));
    }
    if (largest == 0.0) return false;
  }
  *step = memory_.empty() ? std::min(1.0, 0.1 / largest) : 1.0;
  return true;
}

// Backtracking along the projection arc P(x + step d) until the Armijo
// condition f(trial) <= f + c g . (trial - x) holds; the trial point and its
// gradient are left in trial_ and trial_g_.
bool ContinuousSearch::LineSearch(double step, double* trial_f) {
  for (int backtrack = 0; backtrack < kMaxBacktracks; ++backtrack) {
    for (std::size_t i = 0; i < n_; ++i) trial_[i] = x_[i] + step * direction_[i];
    feasible_.Project(trial_);
    double decrease = 0.0;
    for (std::size_t i = 0; i < n_; ++i) decrease += g_[i] * (trial_[i] - x_[i]);
    *trial_f = Evaluate(trial_, trial_g_);
    if (std::isfinite(*trial_f) && *trial_f <= f_ + kArmijo * decrease) return true;
    step *= 0.5;
  }
  return false;
}

LocalResult ContinuousSearch::Run(std::vector<double> x, int max_iterations) {
  feasible_.Project(x);
  x_ = std::move(x);
  f_ = Evaluate(x_, g_);
  if (!std::isfinite(f_)) return result_;
  int stalls = 0;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    double step = 0.0;
    if (IsStationary() || !ChooseDirection(&step)) break;
    double trial_f = kInfinity;
    const bool accepted = LineSearch(step, &trial_f);
    ++result_.iterations;
    if (!accepted) {
      if (memory_.empty()) break;
      memory_.Forget();
      continue;
    }
    std::vector<double> s(n_), y(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      s[i] = trial_[i] - x_[i];
      y[i] = trial_g_[i] - g_[i];
    }
    memory_.Remember(std::move(s), std::move(y));
    stalls = f_ - trial_f < 1e-13 ? stalls + 1 : 0;
    x_.swap(trial_);
    g_.swap(trial_g_);
    f_ = trial_f;
    if (stalls >= kMaxStalls) break;
  }
  result_.gains = std::move(x_);
  result_.value = std::exp(f_);
  return result_;
}

}  // namespace

void Feasible::Project(std::vector<double>& y) const {
  double sum = 0.0;
  for (const double v : y) sum += std::clamp(v, lower, upper);
  if (min_sum > 0.0 && sum < min_sum) {
    double low = 0.0;
    double high = 0.0;
    for (const double v : y) high = std::max(high, upper - v);
    for (int i = 0; i < 200 && high - low > 1e-15 * (1.0 + high); ++i) {
      const double mid = 0.5 * (low + high);
      double s = 0.0;
      for (const double v : y) s += std::clamp(v + mid, lower, upper);
      (s < min_sum ? low : high) = mid;
    }
    for (double& v : y) v += high;
  }
  for (double& v : y) v = std::clamp(v, lower, upper);
}

LocalResult minimize_continuous(const ContinuousObjective& objective, std::vector<double> x,
                                const Feasible& feasible, int max_iterations) {
  ContinuousSearch search(objective, feasible, x.size());
  return search.Run(std::move(x), max_iterations);
}

}  // namespace fss::design_detail
