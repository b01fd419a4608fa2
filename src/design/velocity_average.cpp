// Checks of a velocity distribution for code design and the optimizer's averaged objective
// (design/velocity_average.h; docs/method.md §13).
#include "design/velocity_average.h"

#include <cmath>
#include <utility>

#include "fss/core/error.h"
#include "fss/design/generate.h"

namespace fss::design_detail {

std::string tolerance_text(double tolerance) {
  const double exponent = std::round(std::log10(tolerance));
  if (std::pow(10.0, exponent) == tolerance) {
    return "1e" + std::to_string(static_cast<int>(exponent));
  }
  return format_number(tolerance);
}

bool design_distribution_is_valid(const VelocityDistribution& distribution, double dt,
                                  std::string* error) {
  std::string rule;
  if (!distribution.IsValid(&rule)) {
    if (error != nullptr) *error = rule;
    return false;
  }
  const double reach = distribution.max_abs_velocity() * dt;
  if (!(reach < 2.0)) {
    if (error != nullptr) {
      *error = "velocity distribution '" + escape_control_characters(distribution.text()) +
               "' with dt " + format_exact(dt) +
               ": code design needs |v| dt < 2 at every velocity of its support [" +
               format_exact(distribution.low) + ", " + format_exact(distribution.high) +
               "], which reaches |v| dt = " + format_exact(reach) +
               " (from |v| dt = 2 on every code has K = 0 on the band)";
    }
    return false;
  }
  return true;
}

bool distribution_options_are_valid(const OptimizeOptions& options, std::string* error) {
  const VelocityDistribution& d = *options.velocity_distribution;
  const auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (options.velocity_px_per_slot != OptimizeOptions{}.velocity_px_per_slot) {
    return fail("velocity_px_per_slot = " + format_exact(options.velocity_px_per_slot) +
                ": must stay at its default with a velocity_distribution (the distribution "
                "gives the velocities)");
  }
  std::string rule;
  if (!design_distribution_is_valid(d, options.dt, &rule)) return fail(rule);
  if (d.is_point() && !design_band_is_valid(point_velocity(d), options.dt)) {
    return fail("velocity distribution '" + escape_control_characters(d.text()) +
                "' is the one velocity " + format_exact(point_velocity(d)) + " with dt " +
                format_exact(options.dt) +
                ": the optimizer needs 0 < |velocity| dt < 2 (at v = 0 no motion needs undoing)");
  }
  // One basis of 2 x grid x L doubles per node; a binary search under a restoration holds the
  // restoration objectives' and its own.
  const double nodes = d.kind == VelocityDistributionKind::kDiscrete
                           ? static_cast<double>(d.points.size())
                       : d.is_point() ? 1.0
                                      : kDesignVelocityPanels * kDesignVelocityOrder;
  const bool twice = options.binary && options.restoration.method != RestorationMethod::kInverse;
  const double bytes =
      nodes * 2.0 * options.grid_points * options.length * sizeof(double) * (twice ? 2.0 : 1.0);
  if (bytes > kMaxDesignBasisBytes) {
    return fail("velocity distribution '" + escape_control_characters(d.text()) + "': its " +
                format_number(nodes) + " velocities need " + format_number(bytes / 1e9) +
                " GB of band bases at length " + std::to_string(options.length) +
                ", more than the " + format_number(kMaxDesignBasisBytes / 1e9) +
                " GB allowed: use fewer velocities or a shorter code");
  }
  return true;
}

double support_top(const VelocityDistribution& distribution) {
  return std::abs(distribution.high) >= std::abs(distribution.low) ? distribution.high
                                                                   : distribution.low;
}

double point_velocity(const VelocityDistribution& distribution) {
  return distribution.kind == VelocityDistributionKind::kDiscrete
             ? distribution.points.front().velocity
             : distribution.low;
}

AveragedObjective::AveragedObjective(std::vector<ContinuousObjective> objectives,
                                     std::vector<double> weights, int length)
    : objectives_(std::move(objectives)), weights_(std::move(weights)), length_(length) {}

// F = sum_i w_i F_i, dF / d alpha_k = sum_i w_i dF_i / d alpha_k.
double AveragedObjective::operator()(std::span<const double> gains,
                                     std::span<double> gradient) const {
  std::vector<double> part(gradient.empty() ? 0 : static_cast<std::size_t>(length_));
  for (double& d : gradient) d = 0.0;
  double total = 0.0;
  for (std::size_t i = 0; i < objectives_.size(); ++i) {
    const double value = objectives_[i](gains, part);
    if (!std::isfinite(value)) return kInfinity;
    total += weights_[i] * value;
    for (std::size_t k = 0; k < part.size(); ++k) gradient[k] += weights_[i] * part[k];
  }
  return total;
}

}  // namespace fss::design_detail
