// Code design under a velocity distribution (docs/method.md §13): the checks of a distribution
// for design, and the optimizer's objective averaged over the fixed velocity nodes of
// composite_gauss_nodes; not part of the public interface.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "design/local_search.h"
#include "fss/model/velocity_distribution.h"

namespace fss::design_detail {

// Largest memory the optimizer's band bases may take under a distribution (one basis of
// 2 x grid x L doubles per velocity node), bytes.
inline constexpr double kMaxDesignBasisBytes = 1024.0 * 1024.0 * 1024.0;
// Uniform scan of the support for the worst velocity: this many intervals (the quadrature's
// nodes are candidates too), then kWorstVelocitySteps golden-section steps.
inline constexpr int kWorstVelocityScan = 256;
inline constexpr int kWorstVelocitySteps = 60;

// A tolerance for the reader: "1e-4" for a power of ten, else format_number's digits.
std::string tolerance_text(double tolerance);

// True when `distribution` is valid and |v| dt < 2 over its support (v = 0 included); else
// false with a message naming the distribution (its text()), dt and the rule.
bool design_distribution_is_valid(const VelocityDistribution& distribution, double dt,
                                  std::string* error);

// OptimizeOptions::IsValid's rules for its velocity_distribution (given): velocity_px_per_slot
// at its default, the distribution valid for design (a point one with 0 < |v| dt < 2), and the
// band bases of its velocity nodes within kMaxDesignBasisBytes. False with a message naming the
// field otherwise.
bool distribution_options_are_valid(const OptimizeOptions& options, std::string* error);

// The velocity of the support with the largest |v| (high on a tie): where the code's
// invertibility over a continuous support is decided, and the sinc start's velocity.
double support_top(const VelocityDistribution& distribution);

// The one velocity of a point distribution (is_point()).
double point_velocity(const VelocityDistribution& distribution);

// sum_i w_i F_i(gains), with gradient sum_i w_i grad F_i: the continuous search's objective
// averaged over velocity nodes, F_i the objective at node i (NoiseFigure or RestorationObjective
// at its velocity). Infinite as soon as one F_i is.
class AveragedObjective {
 public:
  AveragedObjective(std::vector<ContinuousObjective> objectives, std::vector<double> weights,
                    int length);
  double operator()(std::span<const double> gains, std::span<double> gradient) const;

 private:
  std::vector<ContinuousObjective> objectives_;
  std::vector<double> weights_;
  int length_;
};

}  // namespace fss::design_detail
