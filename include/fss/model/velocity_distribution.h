// A distribution of velocities (docs/method.md §13): the camera fixes its code before it knows
// the velocity, which is uniform on an interval, normal (truncated), or one of a list of
// velocities with weights. Code design averages its criterion over it; a simulation draws each
// trial's velocity from it. Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fss {

enum class VelocityDistributionKind { kUniform, kNormal, kDiscrete };

// A normal distribution given without bounds is truncated at mean +/- this many SDs (and
// renormalised).
inline constexpr double kDefaultNormalTruncation = 4.0;
// Largest number of velocities of a discrete distribution, and its largest file.
inline constexpr int kMaxDiscreteVelocities = 10000;
inline constexpr std::size_t kMaxVelocityFileBytes = std::size_t{1} << 20;
// Largest |velocity| a distribution accepts, px per slot (design and simulations bound it further
// with dt and the image width).
inline constexpr double kMaxDistributionVelocity = 1e6;

struct VelocityPoint {
  double velocity = 0.0;
  double weight = 0.0;
};

struct VelocityDistribution {
  VelocityDistributionKind kind = VelocityDistributionKind::kUniform;
  // The support [low, high]: the uniform's bounds, the normal's truncation (mean +/- 4 sd unless
  // given), the smallest and largest velocity of a discrete distribution.
  double low = 1.0;
  double high = 1.0;
  // Normal: its mean and standard deviation before truncation; whether the bounds were given.
  double mean = 1.0;
  double sd = 0.0;
  bool bounds_given = false;
  // Discrete: the velocities in increasing order, each once, weights summing to 1.
  std::vector<VelocityPoint> points;
  // Discrete: the file it was read from ("" when built from points).
  std::string source;

  // False with a message naming the value and the rule: finite values, |v| <=
  // kMaxDistributionVelocity, low <= high (uniform), sd > 0 and low < high containing a
  // positive probability (normal), at least one point, positive finite weights (discrete).
  bool IsValid(std::string* error) const;

  // max(|low|, |high|): the velocity whose blur sets a simulation's geometry.
  double max_abs_velocity() const;
  // True when the distribution is one velocity (a uniform of zero width, a discrete one point).
  bool is_point() const;
  // Probability density at v (continuous kinds; 0 outside the support). Discrete: 0.
  double density(double v) const;
  // The smallest v with P(V <= v) >= u, u in [0, 1].
  double quantile(double u) const;
  // Mean of the distribution (after truncation).
  double expected_velocity() const;

  // The text parse_velocity_distribution reads back ("uniform:0.5:1.5", "normal:1:0.2",
  // "normal:1:0.2:0.5:1.5"); a discrete one gives its source file's name, or "discrete" when it
  // has none.
  std::string text() const;
  // In words: "uniform on [0.5, 1.5]", "normal of mean 1, sd 0.2, truncated at mean +/- 4 sd to
  // [0.2, 1.8] and renormalised", "7 velocities from 'v.txt' in [0.5, 1.5]".
  std::string describe() const;
};

// Parses "uniform:LO:HI", "normal:MEAN:SD" or "normal:MEAN:SD:LO:HI" (numbers as the command
// line reads them); false with a one-line message otherwise.
bool parse_velocity_distribution(std::string_view text, VelocityDistribution* distribution,
                                 std::string* error);
// A discrete distribution of `points` (any order; equal velocities merged, weights normalised).
// False with a message naming the offending line (1-based index into `points`).
bool discrete_velocity_distribution(std::vector<VelocityPoint> points, std::string source,
                                    VelocityDistribution* distribution, std::string* error);

// parse_velocity_distribution's forms, or else the path of a file of lines "velocity weight"
// (blank lines and '#' comments skipped; at most kMaxDiscreteVelocities lines of numbers and
// kMaxVelocityFileBytes bytes). Throws a usage fss::Error naming `named_as`
// ("--velocity-distribution") for a spec that is neither a distribution nor an existing file, a
// runtime one naming the file and line when the file cannot be read or does not parse.
VelocityDistribution load_velocity_distribution(const std::string& spec_or_path,
                                                const std::string& named_as);

// The velocity of trial `trial` of a run seeded `seed`: quantile(u), u uniform on [0, 1) from
// its own splitmix64 stream, so that it depends on (seed, trial) only, never on the threads.
double trial_velocity(const VelocityDistribution& distribution, std::uint64_t seed,
                      std::uint64_t trial);

// A quadrature node over the velocity: sum_i weight_i f(velocity_i) approximates E[f(V)].
struct VelocityNode {
  double velocity = 0.0;
  double weight = 0.0;
};

// The fixed composite Gauss-Legendre rule of code optimisation: `order` nodes on each of `panels`
// equal panels of the support, weights times the density (they sum to 1 up to the rule's error
// on the density; normalised to 1). A discrete distribution gives its points; a point
// distribution its one velocity.
inline constexpr int kDesignVelocityPanels = 8;
inline constexpr int kDesignVelocityOrder = 4;
std::vector<VelocityNode> composite_gauss_nodes(const VelocityDistribution& distribution,
                                                int panels = kDesignVelocityPanels,
                                                int order = kDesignVelocityOrder);

// E[f(V)] by adaptive Gauss-Kronrod (7 and 15 nodes): the support split at the interval of
// largest local error estimate until the summed estimate is at most relative_tolerance |E| (or
// max_intervals are spent: converged false). Discrete and point distributions: the exact weighted
// sum. An infinite f at a node makes the value infinite (no refinement). `rule` (when not null)
// receives the final rule, the Kronrod nodes of the final intervals with their weights times the
// density, so that other functions evaluated at the same velocities can be averaged alike.
// `initial_intervals` equal intervals start the refinement: a 15-node rule over the whole support
// can miss the wiggles of an error E(v) with an error estimate far below its error.
struct VelocityExpectation {
  double value = 0.0;
  double error_estimate = 0.0;  // summed |K15 - G7| over the final intervals; 0 when exact
  int evaluations = 0;
  int intervals = 0;  // final intervals (0 for a discrete or point distribution)
  bool converged = true;
};
inline constexpr double kVelocityQuadratureTolerance = 1e-4;
inline constexpr int kMaxVelocityQuadratureIntervals = 256;
inline constexpr int kInitialVelocityQuadratureIntervals = 8;
VelocityExpectation expected_over_velocity(
    const VelocityDistribution& distribution, const std::function<double(double)>& f,
    double relative_tolerance = kVelocityQuadratureTolerance,
    int max_intervals = kMaxVelocityQuadratureIntervals, std::vector<VelocityNode>* rule = nullptr,
    int initial_intervals = kInitialVelocityQuadratureIntervals);

}  // namespace fss
