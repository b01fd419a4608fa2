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
#include "fss/core/error.h"
#include "fss/design/generate.h"
#include "model/noise.h"

namespace fss {

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

// The objectives of the search, made once: the inverse filter's Q_eff M (NoiseFigure; continuous
// gains) or a restoration's E (RestorationObjective), as the continuous search takes it, and the
// binary search's cost. Not copyable: `cost` and `continuous` refer to the members.
class SearchObjectives {
 public:
  explicit SearchObjectives(const OptimizeOptions& options) {
    const double v = options.velocity_px_per_slot;
    const double c = readout_noise_slots(options.sensor, static_cast<std::size_t>(options.length),
                                         options.dt, options.mode, options.snr);
    cost.numerical = options.mode == ShutterMode::kNumerical;
    cost.readout_slots = c;
    if (options.restoration.method != RestorationMethod::kInverse) {
      restoration.emplace(options.length, v, options.dt, options.mode, options.snr,
                          options.restoration, options.grid_points, c);
      cost.restoration = &restoration->band();
      cost.noise_per_q = restoration->noise_per_q();
      continuous = [this](std::span<const double> gains, std::span<double> gradient) {
        return restoration->Evaluate(gains, gradient);
      };
    } else if (!options.binary) {
      noise_figure.emplace(options.length, v, options.dt, options.mode, options.grid_points, c);
      continuous = [this](std::span<const double> gains, std::span<double> gradient) {
        return noise_figure->Evaluate(gains, gradient);
      };
    }
  }
  SearchObjectives(const SearchObjectives&) = delete;
  SearchObjectives& operator=(const SearchObjectives&) = delete;

  std::optional<NoiseFigure> noise_figure;
  std::optional<RestorationObjective> restoration;
  BinaryCost cost;
  ContinuousObjective continuous;
};

// The box code (1, ..., 1, 0, ..., 0) of n ones, n from the light budget to L, with the lowest E
// under the restoration (the first such n on ties).
std::vector<double> best_box_code(const OptimizeOptions& options, const SearchSetting& setting,
                                  const RestorationObjective& objective) {
  std::vector<double> best;
  double best_error = kInfinity;
  for (int n = std::max(setting.min_ones, 1); n <= options.length; ++n) {
    std::vector<double> box(static_cast<std::size_t>(options.length), 0.0);
    std::fill(box.begin(), box.begin() + n, 1.0);
    const double error = objective.Evaluate(box);
    if (error < best_error) {
      best_error = error;
      best = std::move(box);
    }
  }
  return best;
}

// Starting codes: the snapshot first (admissible in every mode without a light
// budget, so the result is never worse than it), under a restoration the best
// box code when it has more than one 1, the sinc code for numerical gains, then
// seeded random codes.
std::vector<std::vector<double>> starting_codes(const OptimizeOptions& options,
                                                const SearchSetting& setting,
                                                const SearchObjectives& objectives) {
  std::vector<std::vector<double>> starts;
  std::mt19937_64 deterministic_rng(start_seed(options.seed, -1));
  starts.push_back(snapshot_code(options.length));
  make_feasible(options, setting, starts.back(), deterministic_rng);
  if (objectives.restoration) {
    std::vector<double> box = best_box_code(options, setting, *objectives.restoration);
    if (gain_sum(box) > 1.0) starts.push_back(std::move(box));
  }
  if (setting.numerical && options.length > 1) {
    starts.push_back(generate_sinc_code(options.length, options.velocity_px_per_slot, options.dt));
  }
  for (int r = 0; r < options.restarts; ++r) starts.push_back(random_start(options, setting, r));
  return starts;
}

// The local search from every start; the best code in result->gains.
void search_from_starts(const OptimizeOptions& options, const SearchSetting& setting,
                        const SearchObjectives& objectives,
                        const std::vector<std::vector<double>>& starts,
                        OptimizationResult* result) {
  const double v = options.velocity_px_per_slot;
  double best = kInfinity;
  for (std::size_t s = 0; s < starts.size(); ++s) {
    const LocalResult local =
        options.binary
            ? design_detail::minimize_binary(options.length, v, options.dt, options.grid_points,
                                             setting.min_ones, starts[s], options.max_iterations,
                                             objectives.cost)
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

}  // namespace

bool OptimizeOptions::IsValid(std::string* error) const {
  if (!code_length_and_dt_are_valid(length, kMaxOptimizedCodeLength, dt, error)) return false;
  const auto fail = [error](const std::string& message) { return invalid(error, message); };
  if (!design_band_is_valid(velocity_px_per_slot, dt)) {
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

// From each start: continuous gains by projected L-BFGS on log(Q M), or log E under a restoration
// (continuous_search.cpp),
// binary gains by a steepest-descent local search over single bit flips, and swaps of a 1 with
// a 0 when no flip helps (binary_search.cpp).
OptimizationResult optimize_code(const OptimizeOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const SearchSetting setting(options);
  const SearchObjectives objectives(options);
  const std::vector<std::vector<double>> starts = starting_codes(options, setting, objectives);

  OptimizationResult result;
  result.options = options;
  result.starts = static_cast<int>(starts.size());
  search_from_starts(options, setting, objectives, starts, &result);
  if (result.gains.empty()) result.gains = snapshot_code(options.length);  // every start failed
  normalize_result(options, setting.numerical, result.gains);
  // Binary gains are admissible in both modes; their Q is the same in both,
  // their readouts are not.
  result.analysis =
      analyze_code(ShutterCode{"optimized", result.gains}, options.velocity_px_per_slot, options.dt,
                   options.snr, options.mode, 0, options.sensor, options.restoration);
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
  if (options.sensor.enabled()) {
    out << "\nSensor: " << describe_design_sensor(options.sensor) << "; snr "
        << format_number(options.snr) << " (" << format_number(options.snr * options.snr / 100.0)
        << " photo-electrons per gray level per slot)";
  }
  if (options.restoration.method != RestorationMethod::kInverse) {
    out << "\nCriterion: " << describe_design_criterion(options.restoration);
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
  std::snprintf(line, sizeof line, "SNR at level 100: %.4f (snapshot %.4f, ratio %.5f; ",
                analysis.snr_level100, analysis.snapshot_snr_level100, analysis.ratio_to_snapshot);
  out << line;
  // The bound is infinite where Q M >= 0 is all it says (|v| dt near 0).
  if (options.restoration.method != RestorationMethod::kInverse) {
    std::snprintf(line, sizeof line, "the Cauchy-Schwarz bound is for the inverse filter only)\n");
  } else if (std::isfinite(analysis.snr_level100_bound)) {
    std::snprintf(line, sizeof line, "Cauchy-Schwarz bound %.4f)\n", analysis.snr_level100_bound);
  } else {
    std::snprintf(line, sizeof line, "no finite Cauchy-Schwarz bound at |v| dt = %g)\n",
                  std::abs(options.velocity_px_per_slot) * options.dt);
  }
  out << line;
  if (options.restoration.method == RestorationMethod::kTikhonov) {
    out << "Regularization: lambda " << format_number(analysis.regularization) << " (snapshot "
        << format_number(analysis.snapshot_regularization) << ")\n";
  }
  return out.str();
}

}  // namespace fss
