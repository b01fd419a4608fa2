#include "fss/design/design.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <random>
#include <sstream>

#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/prediction.h"
#include "fss/model/transfer.h"

namespace fss {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

// Composite Simpson rule with `intervals` (even) sub-intervals.
template <typename F>
double simpson(F f, double a, double b, int intervals) {
  const double h = (b - a) / intervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

// Sub-intervals of the generation integrals: the integrands oscillate at most
// L / 2 times over the band; 16384 Simpson steps put their error below 1e-9.
constexpr int kDesignIntegralIntervals = 16384;

void check_design_arguments(const char* family, int length, double velocity, double dt) {
  if (length < 1) {
    throw_usage_error("the " + std::string(family) + " code needs a length >= 1, got " +
                      std::to_string(length));
  }
  if (!design_band_is_valid(velocity, dt)) {
    throw_usage_error("the " + std::string(family) + " code is designed on the band |theta| <= " +
                      "pi |v| dt, which needs 0 < |v| dt < 2; velocity " + number(velocity) +
                      " and dt " + number(dt) +
                      " give |v| dt = " + number(std::abs(velocity) * dt));
  }
}

std::vector<double> normalized_to_unit_max(std::vector<double> gains) {
  const double sup = gain_max_abs(gains);
  if (sup > 0.0) {
    for (double& g : gains) g /= sup;
  }
  return gains;
}

// 1 / sinc_h(theta) = (theta / 2) / sin(theta / 2), finite for |theta| < 2 pi.
double inverse_sinc_h(double theta) { return 1.0 / sinc_h(theta); }

// Portable uniform double in [0, 1) from a 64-bit generator
// (std::uniform_real_distribution's output is library-specific).
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Seed of the generator of random start r: splitmix64's finalizer of
// seed + (r + 1) * golden ratio, so that nearby seeds give unrelated streams.
std::uint64_t start_seed(std::uint64_t seed, int r) {
  std::uint64_t z = seed + static_cast<std::uint64_t>(r + 1) * 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// The band grid of the optimizer: midpoint nodes xi_j = (j + 1/2) pi / G and
// E_jk = dt sinc_h(theta_j) exp(-i theta_j (k + 1/2)), theta_j = xi_j v dt,
// stored row k by row k so that K = sum_k alpha_k E_k is a sum of rows.
void make_band_basis(int length, double velocity, double dt, int grid, std::vector<double>* re,
                     std::vector<double>* im) {
  re->assign(static_cast<std::size_t>(length) * grid, 0.0);
  im->assign(static_cast<std::size_t>(length) * grid, 0.0);
  for (int j = 0; j < grid; ++j) {
    const double xi = (j + 0.5) * M_PI / grid;
    const double theta = xi * velocity * dt;
    const double amplitude = dt * sinc_h(theta);
    for (int k = 0; k < length; ++k) {
      const double phase = -theta * (k + 0.5);
      (*re)[static_cast<std::size_t>(k) * grid + j] = amplitude * std::cos(phase);
      (*im)[static_cast<std::size_t>(k) * grid + j] = amplitude * std::sin(phase);
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------
// Generation.

std::string to_string(CodeFamily family) {
  switch (family) {
    case CodeFamily::kSinc:
      return "sinc";
    case CodeFamily::kMip:
      return "mip";
    case CodeFamily::kRandom:
      return "random";
    case CodeFamily::kSnapshot:
      return "snapshot";
    case CodeFamily::kAccumulation:
      return "accumulation";
  }
  return "sinc";
}

std::optional<CodeFamily> code_family_from_string(std::string_view text) {
  for (const CodeFamily family : {CodeFamily::kSinc, CodeFamily::kMip, CodeFamily::kRandom,
                                  CodeFamily::kSnapshot, CodeFamily::kAccumulation}) {
    if (text == to_string(family)) return family;
  }
  return std::nullopt;
}

bool design_band_is_valid(double velocity, double dt) {
  const double product = std::abs(velocity) * dt;
  return std::isfinite(product) && product > 0.0 && product < 2.0;
}

std::vector<double> generate_sinc_code(int length, double velocity, double dt) {
  check_design_arguments("sinc", length, velocity, dt);
  const double band = M_PI * std::abs(velocity) * dt;
  const int c = length / 2;
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (int k = 0; k < length; ++k) {
    // T = 1, t0 = c + 1/2: the integrand exp(i theta (k - c)) / sinc_h(theta)
    // is even in its real part and odd in its imaginary part, so the
    // coefficient is (1 / pi) int_0^band cos(theta (k - c)) / sinc_h(theta).
    const double shift = k - c;
    gains[k] = simpson([&](double t) { return std::cos(t * shift) * inverse_sinc_h(t); }, 0.0, band,
                       kDesignIntegralIntervals) /
               M_PI;
  }
  return normalized_to_unit_max(std::move(gains));
}

std::vector<double> generate_mip_code(int length, double velocity, double dt) {
  check_design_arguments("mip", length, velocity, dt);
  const double band = M_PI * std::abs(velocity) * dt;
  const int c = length / 2;
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (int k = 0; k < length; ++k) {
    // T(theta) exp(i theta m) with m = k - c + 1/2: the values at theta and
    // -theta are complex conjugates, so the real part of the coefficient is
    // (1 / pi) int_0^band sqrt(pi / theta) cos(theta m - pi / 4) / sinc_h(theta).
    // With theta = u^2 (d theta = 2 u du) the singularity cancels:
    // (2 sqrt(pi) / pi) int_0^sqrt(band) cos(u^2 m - pi / 4) / sinc_h(u^2) du.
    const double m = k - c + 0.5;
    const double integral = simpson(
        [&](double u) {
          const double theta = u * u;
          return std::cos(theta * m - M_PI / 4.0) * inverse_sinc_h(theta);
        },
        0.0, std::sqrt(band), kDesignIntegralIntervals);
    gains[k] = 2.0 * std::sqrt(M_PI) * integral / M_PI;
  }
  return normalized_to_unit_max(std::move(gains));
}

std::vector<double> generate_random_code(int length, std::uint64_t seed, bool analog) {
  if (length < 1) {
    throw_usage_error("the random code needs a length >= 1, got " + std::to_string(length));
  }
  std::mt19937_64 rng(seed);
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (double& g : gains) {
    const double u = uniform01(rng);
    g = analog ? u : 2.0 * u - 1.0;
  }
  return gains;
}

std::vector<double> snapshot_code(int length) {
  std::vector<double> gains(static_cast<std::size_t>(std::max(length, 0)), 0.0);
  if (!gains.empty()) gains[0] = 1.0;
  return gains;
}

std::vector<double> accumulation_code(int length) {
  return std::vector<double>(static_cast<std::size_t>(std::max(length, 0)), 1.0);
}

bool GenerateOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (length < 1 || length > kMaxGeneratedCodeLength) {
    return fail("length = " + std::to_string(length) + ": must lie in [1, " +
                std::to_string(kMaxGeneratedCodeLength) + "]");
  }
  if (!(std::isfinite(dt) && dt > 0.0)) {
    return fail("dt = " + number(dt) + ": must be finite and > 0");
  }
  if (!std::isfinite(velocity_px_per_slot)) {
    return fail("velocity_px_per_slot = " + number(velocity_px_per_slot) +
                ": must be a finite number");
  }
  if ((family == CodeFamily::kSinc || family == CodeFamily::kMip) &&
      !design_band_is_valid(velocity_px_per_slot, dt)) {
    return fail("velocity_px_per_slot = " + number(velocity_px_per_slot) +
                " with dt = " + number(dt) + ": the " + to_string(family) +
                " code needs 0 < |velocity| dt < 2 (its design band is |theta| <= pi |v| dt)");
  }
  return true;
}

ShutterCode generate_code(const GenerateOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  ShutterCode code;
  code.name = to_string(options.family) + "-L" + std::to_string(options.length);
  switch (options.family) {
    case CodeFamily::kSinc:
      code.gains = generate_sinc_code(options.length, options.velocity_px_per_slot, options.dt);
      break;
    case CodeFamily::kMip:
      code.gains = generate_mip_code(options.length, options.velocity_px_per_slot, options.dt);
      break;
    case CodeFamily::kRandom:
      code.gains = generate_random_code(options.length, options.seed, options.analog);
      break;
    case CodeFamily::kSnapshot:
      code.gains = snapshot_code(options.length);
      break;
    case CodeFamily::kAccumulation:
      code.gains = accumulation_code(options.length);
      break;
  }
  return code;
}

// ---------------------------------------------------------------------------
// Analysis.

double band_mean_inverse_power(std::span<const double> gains, double velocity, double dt,
                               int grid_points) {
  if (grid_points < 1) {
    throw_usage_error("band grid needs at least 1 node, got " + std::to_string(grid_points));
  }
  double sum = 0.0;
  for (int j = 0; j < grid_points; ++j) {
    const double xi = (j + 0.5) * M_PI / grid_points;
    const double power = std::norm(transfer_function(gains, velocity, dt, xi));
    if (!(power > 0.0)) return kInfinity;
    sum += 1.0 / power;
  }
  return sum / grid_points;
}

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

CodeAnalysis analyze_code(std::span<const double> gains, double velocity, double dt, double snr,
                          ShutterMode mode, int grid) {
  if (gains.empty()) throw_usage_error("the code has no gains");
  const std::vector<double> g(gains.begin(), gains.end());
  if (gain_max_abs(g) == 0.0) {
    throw_usage_error("the code has only zero gains: its transfer function is 0");
  }
  if (!std::isfinite(velocity)) {
    throw_usage_error("velocity " + number(velocity) + " must be a finite number");
  }
  if (!(std::isfinite(dt) && dt > 0.0)) {
    throw_usage_error("dt " + number(dt) + " must be finite and > 0");
  }
  if (!(std::isfinite(snr) && snr > 0.0)) {
    throw_usage_error("snr " + number(snr) + " must be finite and > 0");
  }
  if (grid < 0) throw_usage_error("grid " + std::to_string(grid) + " must be >= 0");
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < g.size(); ++k) {
      if (!(g[k] >= 0.0 && g[k] <= 1.0)) {
        throw_usage_error("the code cannot be used in analog mode: gain " + std::to_string(k) +
                          " is " + number(g[k]) + ", analog gains must lie in [0, 1]");
      }
    }
  }

  CodeAnalysis a;
  a.length = static_cast<int>(g.size());
  a.mode = mode;
  a.velocity = velocity;
  a.dt = dt;
  a.snr = snr;
  a.grid = grid;
  a.sum = gain_sum(g);
  a.square_sum = gain_square_sum(g);
  a.normalized_l1 = normalized_l1(g);
  const KernelAnalysis kernel = analyze_kernel(g, velocity, dt);
  a.k0 = kernel.k0;
  a.min_abs = kernel.min_abs;
  a.min_abs_xi = kernel.min_abs_xi;
  a.invertible = kernel.invertible;

  auto mean_inverse = [&](std::span<const double> code) {
    return grid == 0 ? band_mean_inverse_power(code, velocity, dt)
                     : mean_inverse_power(code, velocity, dt, grid);
  };
  a.q = noise_gain(g, dt, mode);
  // As in the simulator's prediction: a code with a zero on the band has no
  // finite M, whatever the grid happens to sample.
  a.m = a.invertible ? mean_inverse(g) : kInfinity;
  a.noise_figure = a.q * a.m;
  a.snr_level100 = snr_level100(a.q, a.m, snr);
  const std::vector<double> snapshot = {1.0};
  const double snapshot_m = mean_inverse(snapshot);
  a.snapshot_snr_level100 = snr_level100(dt, snapshot_m, snr);
  a.ratio_to_snapshot =
      a.snapshot_snr_level100 > 0.0 ? a.snr_level100 / a.snapshot_snr_level100 : 0.0;
  const double bound = noise_figure_lower_bound(velocity, dt);
  a.snr_level100_bound = bound == 0.0 ? kInfinity : snr / std::sqrt(bound);
  return a;
}

// ---------------------------------------------------------------------------
// The objective.

NoiseFigure::NoiseFigure(int length, double velocity, double dt, ShutterMode mode, int grid_points)
    : length_(length), grid_(grid_points), dt_(dt), mode_(mode) {
  if (length < 1) throw_usage_error("NoiseFigure: length " + std::to_string(length) + " < 1");
  if (grid_points < 1) {
    throw_usage_error("NoiseFigure: grid_points " + std::to_string(grid_points) + " < 1");
  }
  make_band_basis(length, velocity, dt, grid_points, &basis_re_, &basis_im_);
}

double NoiseFigure::Evaluate(std::span<const double> gains, std::span<double> gradient) const {
  if (static_cast<int>(gains.size()) != length_ ||
      (!gradient.empty() && static_cast<int>(gradient.size()) != length_)) {
    throw_usage_error("NoiseFigure::Evaluate: expected " + std::to_string(length_) + " gains");
  }
  const std::size_t grid = static_cast<std::size_t>(grid_);
  std::vector<double> re(grid, 0.0), im(grid, 0.0);
  for (int k = 0; k < length_; ++k) {
    const double alpha = gains[k];
    if (alpha == 0.0) continue;
    const double* er = basis_re_.data() + k * grid;
    const double* ei = basis_im_.data() + k * grid;
    for (std::size_t j = 0; j < grid; ++j) {
      re[j] += alpha * er[j];
      im[j] += alpha * ei[j];
    }
  }
  double q = 0.0;
  for (const double alpha : gains) q += mode_ == ShutterMode::kNumerical ? alpha * alpha : alpha;
  q *= dt_;
  if (!(q > 0.0)) return kInfinity;

  double sum = 0.0;
  for (std::size_t j = 0; j < grid; ++j) {
    const double power = re[j] * re[j] + im[j] * im[j];
    if (!(power > 0.0)) return kInfinity;
    const double inverse = 1.0 / power;
    sum += inverse;
    // Keep Re K / |K|^4 and Im K / |K|^4 for the gradient.
    re[j] *= inverse * inverse;
    im[j] *= inverse * inverse;
  }
  const double m = sum / grid_;
  const double value = q * m;
  if (!std::isfinite(value)) return kInfinity;
  if (!gradient.empty()) {
    for (int k = 0; k < length_; ++k) {
      const double* er = basis_re_.data() + k * grid;
      const double* ei = basis_im_.data() + k * grid;
      double dot = 0.0;
      for (std::size_t j = 0; j < grid; ++j) dot += re[j] * er[j] + im[j] * ei[j];
      const double dm = -2.0 * dot / grid_;
      const double dq = mode_ == ShutterMode::kNumerical ? 2.0 * dt_ * gains[k] : dt_;
      gradient[k] = q * dm + m * dq;
    }
  }
  return value;
}

// ---------------------------------------------------------------------------
// Optimization.

bool OptimizeOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (length < 1 || length > kMaxOptimizedCodeLength) {
    return fail("length = " + std::to_string(length) + ": must lie in [1, " +
                std::to_string(kMaxOptimizedCodeLength) + "]");
  }
  if (!(std::isfinite(dt) && dt > 0.0)) {
    return fail("dt = " + number(dt) + ": must be finite and > 0");
  }
  if (!design_band_is_valid(velocity_px_per_slot, dt)) {
    return fail("velocity_px_per_slot = " + number(velocity_px_per_slot) +
                " with dt = " + number(dt) +
                ": must satisfy 0 < |velocity| dt < 2 (at v = 0 no motion needs undoing; from "
                "|v| dt = 2 on every code has K = 0 on the band)");
  }
  if (!(std::isfinite(snr) && snr > 0.0)) {
    return fail("snr = " + number(snr) + ": must be finite and > 0");
  }
  if (!(std::isfinite(min_light_slots) && min_light_slots >= 0.0 && min_light_slots <= length)) {
    return fail("min_light_slots = " + number(min_light_slots) +
                ": must lie in [0, length = " + std::to_string(length) + "]");
  }
  if (min_light_slots > 0.0 && mode == ShutterMode::kNumerical && !binary) {
    return fail("min_light_slots = " + number(min_light_slots) +
                ": a light budget applies to analog or binary gains only (numerical frames "
                "always gather L slots of light)");
  }
  if (restarts < 0) return fail("restarts = " + std::to_string(restarts) + ": must be >= 0");
  if (max_iterations < 1) {
    return fail("max_iterations = " + std::to_string(max_iterations) + ": must be >= 1");
  }
  if (grid_points < 16) {
    return fail("grid_points = " + std::to_string(grid_points) + ": must be >= 16");
  }
  return true;
}

namespace {

struct LocalResult {
  std::vector<double> gains;
  double value = kInfinity;  // Q M
  int iterations = 0;
  int evaluations = 0;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// The feasible set of continuous gains: the box [lower, upper]^L (infinite
// bounds for numerical gains), intersected with sum x >= min_sum.
struct Feasible {
  double lower = -kInfinity;
  double upper = kInfinity;
  double min_sum = 0.0;  // 0: no light budget

  // Euclidean projection. Onto the box it is a clamp; when the clamped point
  // misses the budget, the projection is clamp(y + lambda) with the lambda > 0
  // that meets sum = min_sum (KKT), found by bisection (the sum is monotone).
  void Project(std::vector<double>& y) const {
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
};

// Projected L-BFGS on log(Q M) over a Feasible set. The quasi-Newton
// direction is computed with the gradient restricted to the free variables
// (those not held at a bound of the box by the gradient), and the step is
// projected back onto the set with a backtracking Armijo search along the
// projection arc; when that fails the memory is dropped and the projected
// gradient is used, which always descends.
LocalResult minimize_continuous(const NoiseFigure& objective, std::vector<double> x,
                                const Feasible& feasible, int max_iterations) {
  const double lower = feasible.lower;
  const double upper = feasible.upper;
  constexpr int kMemory = 8;
  constexpr double kArmijo = 1e-4;
  constexpr int kMaxBacktracks = 60;
  const std::size_t n = x.size();
  LocalResult result;

  auto project = [&](std::vector<double>& v) { feasible.Project(v); };
  // f = log(Q M), gradient = grad(Q M) / (Q M).
  auto evaluate = [&](const std::vector<double>& v, std::vector<double>& gradient) {
    ++result.evaluations;
    const double value = objective.Evaluate(v, gradient);
    if (!std::isfinite(value) || !(value > 0.0)) return kInfinity;
    for (double& d : gradient) d /= value;
    return std::log(value);
  };

  project(x);
  std::vector<double> g(n), trial(n), trial_g(n), direction(n);
  double f = evaluate(x, g);
  if (!std::isfinite(f)) return result;
  std::deque<std::vector<double>> memory_s, memory_y;
  std::deque<double> memory_rho;
  auto forget = [&] {
    memory_s.clear();
    memory_y.clear();
    memory_rho.clear();
  };
  std::vector<bool> is_free(n);
  int stalls = 0;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    // Stationarity: x = P(x - g).
    for (std::size_t i = 0; i < n; ++i) trial[i] = x[i] - g[i];
    project(trial);
    double projected_gradient = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      is_free[i] = !((x[i] <= lower && g[i] > 0.0) || (x[i] >= upper && g[i] < 0.0));
      projected_gradient = std::max(projected_gradient, std::abs(x[i] - trial[i]));
    }
    if (projected_gradient < 1e-10) break;

    // Two-loop recursion on the free part of the gradient.
    for (std::size_t i = 0; i < n; ++i) direction[i] = is_free[i] ? g[i] : 0.0;
    std::vector<double> alphas(memory_s.size());
    for (std::size_t m = memory_s.size(); m-- > 0;) {
      alphas[m] = memory_rho[m] * dot(memory_s[m], direction);
      for (std::size_t i = 0; i < n; ++i) direction[i] -= alphas[m] * memory_y[m][i];
    }
    if (!memory_s.empty()) {
      const double gamma =
          dot(memory_s.back(), memory_y.back()) / dot(memory_y.back(), memory_y.back());
      for (double& d : direction) d *= gamma;
    }
    for (std::size_t m = 0; m < memory_s.size(); ++m) {
      const double beta = memory_rho[m] * dot(memory_y[m], direction);
      for (std::size_t i = 0; i < n; ++i) direction[i] += (alphas[m] - beta) * memory_s[m][i];
    }
    double slope = 0.0;
    double largest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      direction[i] = is_free[i] ? -direction[i] : 0.0;
      slope += direction[i] * g[i];
      largest = std::max(largest, std::abs(direction[i]));
    }
    if (!(slope < 0.0) || memory_s.empty()) {
      // Steepest descent, with a first step of at most 0.1 per gain.
      forget();
      largest = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        direction[i] = is_free[i] ? -g[i] : 0.0;
        largest = std::max(largest, std::abs(direction[i]));
      }
      if (largest == 0.0) break;
    }
    double step = memory_s.empty() ? std::min(1.0, 0.1 / largest) : 1.0;

    bool accepted = false;
    double trial_f = kInfinity;
    for (int backtrack = 0; backtrack < kMaxBacktracks; ++backtrack) {
      for (std::size_t i = 0; i < n; ++i) trial[i] = x[i] + step * direction[i];
      project(trial);
      double decrease = 0.0;
      for (std::size_t i = 0; i < n; ++i) decrease += g[i] * (trial[i] - x[i]);
      trial_f = evaluate(trial, trial_g);
      if (std::isfinite(trial_f) && trial_f <= f + kArmijo * decrease) {
        accepted = true;
        break;
      }
      step *= 0.5;
    }
    ++result.iterations;
    if (!accepted) {
      if (memory_s.empty()) break;
      forget();
      continue;
    }
    std::vector<double> s(n), y(n);
    for (std::size_t i = 0; i < n; ++i) {
      s[i] = trial[i] - x[i];
      y[i] = trial_g[i] - g[i];
    }
    const double sy = dot(s, y);
    if (sy > 1e-12 * std::sqrt(dot(s, s) * dot(y, y))) {
      memory_s.push_back(std::move(s));
      memory_y.push_back(std::move(y));
      memory_rho.push_back(1.0 / sy);
      if (static_cast<int>(memory_s.size()) > kMemory) {
        memory_s.pop_front();
        memory_y.pop_front();
        memory_rho.pop_front();
      }
    }
    stalls = f - trial_f < 1e-13 ? stalls + 1 : 0;
    x.swap(trial);
    g.swap(trial_g);
    f = trial_f;
    if (stalls >= 5) break;
  }
  result.gains = std::move(x);
  result.value = std::exp(f);
  return result;
}

// Steepest-descent local search on binary codes. A move flips one gain or,
// when no flip helps, swaps a 1 with a 0 (which keeps the light, so the search
// can move along a light budget); the move that lowers Q M the most is made,
// until none lowers it. K is updated incrementally (K +/- E_k), so one pass
// over the neighbours costs G operations per neighbour. Q = dt * (number of
// ones) in both modes.
LocalResult minimize_binary(int length, double velocity, double dt, int grid, int min_ones,
                            std::vector<double> x, int max_moves) {
  std::vector<double> basis_re, basis_im;
  make_band_basis(length, velocity, dt, grid, &basis_re, &basis_im);
  const std::size_t g = static_cast<std::size_t>(grid);
  std::vector<double> re(g, 0.0), im(g, 0.0);
  int ones = 0;
  auto add_row = [&](int k, double sign) {
    for (std::size_t j = 0; j < g; ++j) {
      re[j] += sign * basis_re[k * g + j];
      im[j] += sign * basis_im[k * g + j];
    }
  };
  for (int k = 0; k < length; ++k) {
    x[k] = x[k] > 0.5 ? 1.0 : 0.0;
    if (x[k] == 1.0) {
      ++ones;
      add_row(k, 1.0);
    }
  }
  // Q M after adding sign_a E_a + sign_b E_b to K (b = -1: no second row).
  auto value_after = [&](int a, double sign_a, int b, double sign_b, int count) {
    if (count == 0 || count < min_ones) return kInfinity;
    const double* ar = basis_re.data() + a * g;
    const double* ai = basis_im.data() + a * g;
    const double* br = basis_re.data() + (b < 0 ? a : b) * g;
    const double* bi = basis_im.data() + (b < 0 ? a : b) * g;
    const double weight_b = b < 0 ? 0.0 : sign_b;
    double sum = 0.0;
    for (std::size_t j = 0; j < g; ++j) {
      const double r = re[j] + sign_a * ar[j] + weight_b * br[j];
      const double i = im[j] + sign_a * ai[j] + weight_b * bi[j];
      const double power = r * r + i * i;
      if (!(power > 0.0)) return kInfinity;
      sum += 1.0 / power;
    }
    return dt * count * sum / grid;
  };
  LocalResult result;
  result.evaluations = 1;
  double current = value_after(0, 0.0, -1, 0.0, ones);
  for (int move = 0; move < max_moves; ++move) {
    int best_a = -1;
    int best_b = -1;
    double best = current;
    for (int k = 0; k < length; ++k) {
      const double sign = x[k] == 1.0 ? -1.0 : 1.0;
      const double candidate = value_after(k, sign, -1, 0.0, ones + static_cast<int>(sign));
      ++result.evaluations;
      if (candidate < best * (1.0 - 1e-12)) {
        best = candidate;
        best_a = k;
      }
    }
    if (best_a < 0) {
      for (int a = 0; a < length; ++a) {
        if (x[a] != 1.0) continue;
        for (int b = 0; b < length; ++b) {
          if (x[b] != 0.0) continue;
          const double candidate = value_after(a, -1.0, b, 1.0, ones);
          ++result.evaluations;
          if (candidate < best * (1.0 - 1e-12)) {
            best = candidate;
            best_a = a;
            best_b = b;
          }
        }
      }
    }
    if (best_a < 0) break;
    const double sign = x[best_a] == 1.0 ? -1.0 : 1.0;
    add_row(best_a, sign);
    x[best_a] = sign > 0.0 ? 1.0 : 0.0;
    ones += static_cast<int>(sign);
    if (best_b >= 0) {
      add_row(best_b, 1.0);
      x[best_b] = 1.0;
      ++ones;
    }
    current = best;
    ++result.iterations;
  }
  result.gains = std::move(x);
  result.value = current;
  return result;
}

}  // namespace

OptimizationResult optimize_code(const OptimizeOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const int length = options.length;
  const double v = options.velocity_px_per_slot;
  const double dt = options.dt;

  const bool numerical = options.mode == ShutterMode::kNumerical && !options.binary;
  const int min_ones = static_cast<int>(std::ceil(options.min_light_slots - 1e-9));
  Feasible feasible;
  if (!numerical) {
    feasible.lower = 0.0;
    feasible.upper = 1.0;
    feasible.min_sum = options.min_light_slots;
  }

  // Starting codes: the snapshot first (admissible in every mode without a
  // light budget, so the result is never worse than it), the sinc code for
  // numerical gains, then seeded random codes. Starts that miss the light
  // budget are moved onto it: binary ones get 1s at random places, analog
  // ones are projected.
  auto make_feasible = [&](std::vector<double>& start, std::mt19937_64& rng) {
    if (options.binary) {
      int ones = static_cast<int>(std::count(start.begin(), start.end(), 1.0));
      while (ones < min_ones) {
        const auto k = static_cast<std::size_t>(uniform01(rng) * length);
        if (start[k] == 0.0) {
          start[k] = 1.0;
          ++ones;
        }
      }
    } else {
      feasible.Project(start);
    }
  };
  std::vector<std::vector<double>> starts;
  std::mt19937_64 deterministic_rng(start_seed(options.seed, -1));
  starts.push_back(snapshot_code(length));
  make_feasible(starts.back(), deterministic_rng);
  if (numerical && length > 1) starts.push_back(generate_sinc_code(length, v, dt));
  for (int r = 0; r < options.restarts; ++r) {
    // Each start has its own generator, so that more restarts only add starts.
    std::mt19937_64 rng(start_seed(options.seed, r));
    std::vector<double> start(static_cast<std::size_t>(length));
    if (options.binary) {
      // A density drawn per start, so that sparse and dense codes are tried.
      const double density = 0.05 + 0.6 * uniform01(rng);
      for (double& g : start) g = uniform01(rng) < density ? 1.0 : 0.0;
    } else {
      for (double& g : start) g = numerical ? 2.0 * uniform01(rng) - 1.0 : uniform01(rng);
    }
    make_feasible(start, rng);
    starts.push_back(std::move(start));
  }

  OptimizationResult result;
  result.options = options;
  result.starts = static_cast<int>(starts.size());
  std::optional<NoiseFigure> objective;
  if (!options.binary) objective.emplace(length, v, dt, options.mode, options.grid_points);
  double best = kInfinity;
  for (std::size_t s = 0; s < starts.size(); ++s) {
    const LocalResult local =
        options.binary
            ? minimize_binary(length, v, dt, options.grid_points, min_ones, starts[s],
                              options.max_iterations)
            : minimize_continuous(*objective, starts[s], feasible, options.max_iterations);
    result.iterations += local.iterations;
    result.evaluations += local.evaluations;
    if (local.value < best) {
      best = local.value;
      result.gains = local.gains;
      result.best_start = static_cast<int>(s);
    }
  }
  if (result.gains.empty()) result.gains = snapshot_code(length);  // every start failed
  // Numerical: max |alpha| = 1 changes nothing. Analog: max alpha = 1 can only
  // lower Q M (it scales by 1 / c). Binary codes are left as they are.
  if (!options.binary) {
    const double sup = gain_max_abs(result.gains);
    if (sup > 0.0) {
      for (double& g : result.gains) g /= sup;
    }
    if (!numerical) {
      for (double& g : result.gains) g = std::clamp(g, 0.0, 1.0);
    }
  }
  result.analysis = analyze_code(result.gains, v, dt, options.snr,
                                 options.binary ? ShutterMode::kAnalog : options.mode);
  result.analysis.mode = options.mode;
  return result;
}

std::string OptimizationResult::FullReport() const {
  std::ostringstream out;
  char line[256];
  const std::string kind =
      options.binary ? "binary" : (options.mode == ShutterMode::kAnalog ? "analog" : "numerical");
  std::snprintf(line, sizeof line, "Optimized %s code: L = %d, velocity %g, dt %g", kind.c_str(),
                options.length, options.velocity_px_per_slot, options.dt);
  out << line;
  if (options.min_light_slots > 0.0) {
    std::snprintf(line, sizeof line, ", light >= %g slots", options.min_light_slots);
    out << line;
  }
  std::snprintf(line, sizeof line,
                "\nSearch: %d starts (seed %llu, best from start %d), %d iterations, %d "
                "evaluations\n",
                starts, static_cast<unsigned long long>(options.seed), best_start, iterations,
                evaluations);
  out << line;
  std::snprintf(line, sizeof line,
                "Sum of gains %.4f, sum of squares %.4f, normalized L1 norm %.4f\n", analysis.sum,
                analysis.square_sum, analysis.normalized_l1);
  out << line;
  std::snprintf(line, sizeof line,
                "SNR at level 100: %.4f (snapshot %.4f, ratio %.5f; Cauchy-Schwarz bound %.4f)\n",
                analysis.snr_level100, analysis.snapshot_snr_level100, analysis.ratio_to_snapshot,
                analysis.snr_level100_bound);
  out << line;
  return out.str();
}

}  // namespace fss
