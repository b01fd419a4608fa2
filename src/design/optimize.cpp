#include "fss/design/optimize.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <sstream>

#include "design/local_search.h"
#include "design/option_checks.h"
#include "design/restoration_figure.h"
#include "design/velocity_average.h"
#include "fss/core/error.h"
#include "fss/design/generate.h"
#include "model/noise.h"

namespace fss {

using design_detail::AveragedObjective;
using design_detail::BinaryCost;
using design_detail::code_length_and_dt_are_valid;
using design_detail::ContinuousObjective;
using design_detail::Feasible;
using design_detail::invalid;
using design_detail::kInfinity;
using design_detail::LocalResult;
using design_detail::RestorationObjective;
using design_detail::uniform01;

namespace {

// Seed of the generator of random start r (r = -1: the deterministic starts'
// generator): splitmix64 of seed + r * gamma, so that nearby seeds give
// unrelated streams.
std::uint64_t start_seed(std::uint64_t seed, int r) {
  std::uint64_t state = seed + static_cast<std::uint64_t>(r) * kSplitmix64Gamma;
  return splitmix64(state);
}

// What the options ask of the search, derived once.
struct SearchSetting {
  bool numerical = true;  // any real gains
  int min_ones = 0;       // binary: the light budget in ones
  Feasible feasible;      // continuous gains: the box and the budget

  explicit SearchSetting(const OptimizeOptions& options)
      : numerical(options.mode == ShutterMode::kNumerical && !options.binary),
        min_ones(static_cast<int>(std::ceil(options.min_light_slots - 1e-9))) {
    if (!numerical) {
      feasible.lower = 0.0;
      feasible.upper = 1.0;
      feasible.min_sum = options.min_light_slots;
    }
  }
};

// Moves a start that misses the light budget onto it: binary starts get 1s at
// random places, continuous ones are projected.
void make_feasible(const OptimizeOptions& options, const SearchSetting& setting,
                   std::vector<double>& start, std::mt19937_64& rng) {
  if (!options.binary) {
    setting.feasible.Project(start);
    return;
  }
  int ones = static_cast<int>(std::count(start.begin(), start.end(), 1.0));
  while (ones < setting.min_ones) {
    const auto k = static_cast<std::size_t>(uniform01(rng) * options.length);
    if (start[k] == 0.0) {
      start[k] = 1.0;
      ++ones;
    }
  }
}

// Random start r, from its own generator, so that more restarts only add
// starts.
std::vector<double> random_start(const OptimizeOptions& options, const SearchSetting& setting,
                                 int r) {
  std::mt19937_64 rng(start_seed(options.seed, r));
  std::vector<double> start(static_cast<std::size_t>(options.length));
  if (options.binary) {
    // A density drawn per start, so that sparse and dense codes are tried.
    const double density = 0.05 + 0.6 * uniform01(rng);
    for (double& g : start) g = uniform01(rng) < density ? 1.0 : 0.0;
  } else {
    for (double& g : start) g = setting.numerical ? 2.0 * uniform01(rng) - 1.0 : uniform01(rng);
  }
  make_feasible(options, setting, start, rng);
  return start;
}

// The velocity nodes of the criterion: the one velocity (weight 1), or the distribution's
// composite Gauss rule (a discrete distribution: its velocities).
std::vector<VelocityNode> criterion_velocities(const OptimizeOptions& options) {
  if (!options.velocity_distribution) return {{options.velocity_px_per_slot, 1.0}};
  return composite_gauss_nodes(*options.velocity_distribution);
}

// The velocity the sinc start is designed for: the options' one, or the support's largest |v|
// (where the code must stay invertible for every velocity of the support).
double design_velocity(const OptimizeOptions& options) {
  return options.velocity_distribution ? design_detail::support_top(*options.velocity_distribution)
                                       : options.velocity_px_per_slot;
}

// The objectives of the search, made once per velocity node: the inverse filter's Q_eff M
// (NoiseFigure; continuous gains) or a restoration's E (RestorationObjective), as the continuous
// search takes it (their weighted sum over the nodes, or the one node's own), and the binary
// search's cost. Not copyable: `cost` and `continuous` refer to the members.
class SearchObjectives {
 public:
  explicit SearchObjectives(const OptimizeOptions& options) : nodes(criterion_velocities(options)) {
    const double c = readout_noise_slots(options.sensor, static_cast<std::size_t>(options.length),
                                         options.dt, options.mode, options.snr);
    cost.numerical = options.mode == ShutterMode::kNumerical;
    cost.readout_slots = c;
    std::vector<design_detail::ContinuousObjective> parts;
    if (options.restoration.method != RestorationMethod::kInverse) {
      restorations.reserve(nodes.size());
      for (const VelocityNode& node : nodes) {
        restorations.emplace_back(options.length, node.velocity, options.dt, options.mode,
                                  options.snr, options.restoration, options.grid_points, c);
      }
      cost.restoration = &restorations.front().band();
      cost.noise_per_q = restorations.front().noise_per_q();
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        parts.push_back([this, i](std::span<const double> gains, std::span<double> gradient) {
          return restorations[i].Evaluate(gains, gradient);
        });
      }
    } else if (!options.binary) {
      noise_figures.reserve(nodes.size());
      for (const VelocityNode& node : nodes) {
        noise_figures.emplace_back(options.length, node.velocity, options.dt, options.mode,
                                   options.grid_points, c);
      }
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        parts.push_back([this, i](std::span<const double> gains, std::span<double> gradient) {
          return noise_figures[i].Evaluate(gains, gradient);
        });
      }
    }
    if (parts.size() == 1) {
      continuous = parts.front();
    } else if (!parts.empty()) {
      std::vector<double> weights;
      for (const VelocityNode& node : nodes) weights.push_back(node.weight);
      continuous = AveragedObjective(std::move(parts), std::move(weights), options.length);
    }
  }
  SearchObjectives(const SearchObjectives&) = delete;
  SearchObjectives& operator=(const SearchObjectives&) = delete;

  // E of `gains` under the restoration: the one node's, or sum_i w_i E_i over the nodes.
  double RestorationError(std::span<const double> gains) const {
    if (restorations.size() == 1) return restorations.front().Evaluate(gains);
    double total = 0.0;
    for (std::size_t i = 0; i < restorations.size(); ++i) {
      total += nodes[i].weight * restorations[i].Evaluate(gains);
    }
    return total;
  }

  std::vector<VelocityNode> nodes;
  std::vector<NoiseFigure> noise_figures;
  std::vector<RestorationObjective> restorations;
  BinaryCost cost;
  ContinuousObjective continuous;
};

// The box code (1, ..., 1, 0, ..., 0) of n ones, n from the light budget to L, with the lowest E
// under the restoration (the first such n on ties).
std::vector<double> best_box_code(const OptimizeOptions& options, const SearchSetting& setting,
                                  const SearchObjectives& objectives) {
  std::vector<double> best;
  double best_error = kInfinity;
  for (int n = std::max(setting.min_ones, 1); n <= options.length; ++n) {
    std::vector<double> box(static_cast<std::size_t>(options.length), 0.0);
    std::fill(box.begin(), box.begin() + n, 1.0);
    const double error = objectives.RestorationError(box);
    if (error < best_error) {
      best_error = error;
      best = std::move(box);
    }
  }
  return best;
}

// Starting codes: the snapshot first (admissible in every mode without a light
// budget, so the result is never worse than it), under a restoration the best
// box code when it has more than one 1, the sinc code for numerical gains,
// under a distribution `speed_optimum` (when not empty), then seeded random
// codes.
std::vector<std::vector<double>> starting_codes(const OptimizeOptions& options,
                                                const SearchSetting& setting,
                                                const SearchObjectives& objectives,
                                                std::vector<double> speed_optimum) {
  std::vector<std::vector<double>> starts;
  std::mt19937_64 deterministic_rng(start_seed(options.seed, -1));
  starts.push_back(snapshot_code(options.length));
  make_feasible(options, setting, starts.back(), deterministic_rng);
  if (!objectives.restorations.empty()) {
    std::vector<double> box = best_box_code(options, setting, objectives);
    if (gain_sum(box) > 1.0) starts.push_back(std::move(box));
  }
  if (setting.numerical && options.length > 1) {
    starts.push_back(generate_sinc_code(options.length, design_velocity(options), options.dt));
  }
  if (!speed_optimum.empty()) starts.push_back(std::move(speed_optimum));
  for (int r = 0; r < options.restarts; ++r) starts.push_back(random_start(options, setting, r));
  return starts;
}

// The local search from every start; the best code in result->gains.
void search_from_starts(const OptimizeOptions& options, const SearchSetting& setting,
                        const SearchObjectives& objectives,
                        const std::vector<std::vector<double>>& starts,
                        OptimizationResult* result) {
  double best = kInfinity;
  for (std::size_t s = 0; s < starts.size(); ++s) {
    const LocalResult local =
        options.binary
            ? design_detail::minimize_binary(options.length, objectives.nodes, options.dt,
                                             options.grid_points, setting.min_ones, starts[s],
                                             options.max_iterations, objectives.cost)
            : design_detail::minimize_continuous(objectives.continuous, starts[s], setting.feasible,
                                                 options.max_iterations);
    result->iterations += local.iterations;
    result->evaluations += local.evaluations;
    if (local.value < best) {
      best = local.value;
      result->gains = local.gains;
      result->best_start = static_cast<int>(s);
    }
  }
}

// Numerical: max |alpha| = 1 changes nothing. Analog: max alpha = 1 can only
// lower Q M (it scales by 1 / c). Binary codes are left as they are.
void normalize_result(const OptimizeOptions& options, bool numerical, std::vector<double>& gains) {
  if (options.binary) return;
  const double sup = gain_max_abs(gains);
  if (sup > 0.0) {
    for (double& g : gains) g /= sup;
  }
  if (!numerical) {
    for (double& g : gains) g = std::clamp(g, 0.0, 1.0);
  }
}

// The distribution and the rules that average the criterion over it, for FullReport.
std::string velocity_rules(const OptimizationResult& result) {
  const VelocityDistribution& d = *result.options.velocity_distribution;
  if (d.is_point()) return d.describe() + ": one velocity, the single-velocity criterion";
  if (d.kind == VelocityDistributionKind::kDiscrete) {
    return d.describe() + "; criterion averaged over it: the weighted sum over its " +
           std::to_string(d.points.size()) + " velocities (optimisation and reported figure)";
  }
  const CodeAnalysis& a = result.analysis;
  return d.describe() + "; criterion averaged over it: composite Gauss rule " +
         std::to_string(kDesignVelocityPanels) + " panels x " +
         std::to_string(kDesignVelocityOrder) +
         " nodes (optimisation), adaptive Gauss-Kronrod to " +
         design_detail::tolerance_text(kVelocityQuadratureTolerance) +
         " (reported figure: " + std::to_string(a.quadrature_evaluations) + " evaluations" +
         (a.quadrature_converged
              ? ""
              : ", the tolerance not met within " +
                    std::to_string(kMaxVelocityQuadratureIntervals) + " intervals") +
         ")";
}

// The worst velocity of an averaged analysis and its SNR, or where the code is not invertible.
std::string worst_velocity_line(const CodeAnalysis& a) {
  char line[256];
  if (a.worst_snr_level100 > 0.0) {
    std::snprintf(line, sizeof line, "Worst velocity in the support: %g (SNR at level 100 %.4f)\n",
                  a.worst_velocity, a.worst_snr_level100);
  } else {
    std::snprintf(line, sizeof line,
                  "Not invertible at velocity %g: the expected error is infinite\n",
                  a.worst_velocity);
  }
  return line;
}

}  // namespace

bool OptimizeOptions::IsValid(std::string* error) const {
  if (!code_length_and_dt_are_valid(length, kMaxOptimizedCodeLength, dt, error)) return false;
  const auto fail = [error](const std::string& message) { return invalid(error, message); };
  if (velocity_distribution) {
    if (!design_detail::distribution_options_are_valid(*this, error)) return false;
  } else if (!design_band_is_valid(velocity_px_per_slot, dt)) {
    return fail("velocity_px_per_slot = " + format_exact(velocity_px_per_slot) +
                " with dt = " + format_exact(dt) +
                ": must satisfy 0 < |velocity| dt < 2 (at v = 0 no motion needs undoing; from "
                "|v| dt = 2 on every code has K = 0 on the band)");
  }
  if (!(std::isfinite(snr) && snr > 0.0)) {
    return fail("snr = " + format_exact(snr) + ": must be finite and > 0");
  }
  std::string sensor_error;
  if (!sensor.IsValid(&sensor_error)) return fail("sensor." + sensor_error);
  if (sensor.full_well_electrons) {
    return fail("sensor.full_well_electrons = " + format_number(*sensor.full_well_electrons) +
                ": the figure of merit of a code is linear in the charge and has no full well");
  }
  if (!std::isfinite(readout_noise_slots(sensor, static_cast<std::size_t>(std::max(length, 1)), dt,
                                         mode, snr))) {
    return fail("the sensor's readout noise (" + describe_design_sensor(sensor) + ") at snr " +
                format_exact(snr) +
                " is more than 1e308 slots of level-100 light, beyond double precision: lower "
                "the read noise, dark current or ADC gain, or raise snr");
  }
  if (!(std::isfinite(min_light_slots) && min_light_slots >= 0.0 && min_light_slots <= length)) {
    return fail("min_light_slots = " + format_exact(min_light_slots) +
                ": must lie in [0, length = " + std::to_string(length) + "]");
  }
  if (min_light_slots > 0.0 && mode == ShutterMode::kNumerical && !binary) {
    return fail("min_light_slots = " + format_exact(min_light_slots) +
                ": a light budget applies to analog or binary gains only (numerical frames "
                "always gather L slots of light)");
  }
  if (restarts < 0 || restarts > kMaxRestarts) {
    return fail("restarts = " + std::to_string(restarts) + ": must lie in [0, " +
                std::to_string(kMaxRestarts) + "]");
  }
  if (max_iterations < 1 || max_iterations > kMaxIterations) {
    return fail("max_iterations = " + std::to_string(max_iterations) + ": must lie in [1, " +
                std::to_string(kMaxIterations) + "]");
  }
  std::string restoration_error;
  if (!restoration.IsValid(&restoration_error)) return fail("restoration." + restoration_error);
  if (restoration.method == RestorationMethod::kWiener && restoration.prior == PriorKind::kOracle) {
    return fail(
        "restoration.prior = oracle: code design has no image, so there is no oracle spectrum "
        "(use a power-law prior)");
  }
  if (grid_points < 16 || grid_points > kMaxObjectiveGridPoints) {
    return fail("grid_points = " + std::to_string(grid_points) + ": must lie in [16, " +
                std::to_string(kMaxObjectiveGridPoints) + "]");
  }
  return true;
}

namespace {

// E|V|, the mean speed of a distribution.
double mean_speed(const VelocityDistribution& d) {
  return expected_over_velocity(d, [](double v) { return std::abs(v); }).value;
}

// The search for `search` (a single velocity or a distribution that is not a point): the best
// code, normalised, with the counts of the search. Under a distribution the same search at its
// mean speed E|V| runs first and its optimum is a start (its counts included), so that the
// result is no worse than that single-velocity optimum under the optimisation's rule.
OptimizationResult run_search(const OptimizeOptions& search) {
  OptimizationResult result;
  std::vector<double> speed_optimum;
  if (search.velocity_distribution) {
    OptimizeOptions single = search;
    single.velocity_distribution.reset();
    single.velocity_px_per_slot = mean_speed(*search.velocity_distribution);
    if (design_band_is_valid(single.velocity_px_per_slot, single.dt)) {
      const OptimizationResult inner = run_search(single);
      speed_optimum = inner.gains;
      result.iterations = inner.iterations;
      result.evaluations = inner.evaluations;
    }
  }
  const SearchSetting setting(search);
  const SearchObjectives objectives(search);
  const std::vector<std::vector<double>> starts =
      starting_codes(search, setting, objectives, std::move(speed_optimum));
  result.starts = static_cast<int>(starts.size());
  search_from_starts(search, setting, objectives, starts, &result);
  if (result.gains.empty()) result.gains = snapshot_code(search.length);  // every start failed
  normalize_result(search, setting.numerical, result.gains);
  return result;
}

}  // namespace

// From each start: continuous gains by projected L-BFGS on log(Q M), or log E under a restoration
// (continuous_search.cpp),
// binary gains by a steepest-descent local search over single bit flips, and swaps of a 1 with
// a 0 when no flip helps (binary_search.cpp).
OptimizationResult optimize_code(const OptimizeOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  // A point distribution is the search at its one velocity.
  OptimizeOptions search = options;
  if (options.velocity_distribution && options.velocity_distribution->is_point()) {
    search.velocity_px_per_slot = design_detail::point_velocity(*options.velocity_distribution);
    search.velocity_distribution.reset();
  }
  OptimizationResult result = run_search(search);
  result.options = options;
  // Binary gains are admissible in both modes; their Q is the same in both,
  // their readouts are not.
  const ShutterCode code{"optimized", result.gains};
  result.analysis =
      options.velocity_distribution
          ? analyze_code(code, *options.velocity_distribution, options.dt, options.snr,
                         options.mode, 0, options.sensor, options.restoration)
          : analyze_code(code, options.velocity_px_per_slot, options.dt, options.snr, options.mode,
                         0, options.sensor, options.restoration);
  return result;
}

std::string OptimizationResult::FullReport() const {
  std::ostringstream out;
  char line[256];
  const std::string kind =
      options.binary ? "binary" : (options.mode == ShutterMode::kAnalog ? "analog" : "numerical");
  if (options.velocity_distribution) {
    std::snprintf(line, sizeof line, "Optimized %s code: L = %d, dt %g", kind.c_str(),
                  options.length, options.dt);
  } else {
    std::snprintf(line, sizeof line, "Optimized %s code: L = %d, velocity %g, dt %g", kind.c_str(),
                  options.length, options.velocity_px_per_slot, options.dt);
  }
  out << line;
  if (options.min_light_slots > 0.0) {
    std::snprintf(line, sizeof line, ", light >= %g slots", options.min_light_slots);
    out << line;
  }
  if (options.sensor.enabled()) {
    out << "\nSensor: " << describe_design_sensor(options.sensor) << "; snr "
        << format_number(options.snr) << " (" << format_number(options.snr * options.snr / 100.0)
        << " photo-electrons per gray level per slot)";
  }
  if (options.restoration.method != RestorationMethod::kInverse) {
    out << "\nCriterion: " << describe_design_criterion(options.restoration);
  }
  if (options.velocity_distribution) out << "\nVelocity: " << velocity_rules(*this);
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
  std::snprintf(line, sizeof line, "SNR at level 100: %.4f (snapshot %.4f, ratio %.5f; ",
                analysis.snr_level100, analysis.snapshot_snr_level100, analysis.ratio_to_snapshot);
  out << line;
  // The bound is infinite where Q M >= 0 is all it says (|v| dt near 0).
  if (options.restoration.method != RestorationMethod::kInverse) {
    std::snprintf(line, sizeof line, "the Cauchy-Schwarz bound is for the inverse filter only)\n");
  } else if (std::isfinite(analysis.snr_level100_bound)) {
    std::snprintf(line, sizeof line, "Cauchy-Schwarz bound %s%.4f)\n",
                  options.velocity_distribution ? "of the average " : "",
                  analysis.snr_level100_bound);
  } else {
    std::snprintf(line, sizeof line, "no finite Cauchy-Schwarz bound at |v| dt = %g)\n",
                  std::abs(options.velocity_px_per_slot) * options.dt);
  }
  out << line;
  if (options.velocity_distribution) out << worst_velocity_line(analysis);
  if (options.restoration.method == RestorationMethod::kTikhonov) {
    out << "Regularization: lambda " << format_number(analysis.regularization) << " (snapshot "
        << format_number(analysis.snapshot_regularization) << ")"
        << (options.velocity_distribution && !options.restoration.regularization
                ? " at the worst velocity; each velocity is restored with its own optimal lambda"
                : "")
        << "\n";
  }
  return out.str();
}

}  // namespace fss
