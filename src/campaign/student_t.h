// Student's t distribution, for the tolerance of `campaign check` (docs/campaign.md,
// "Regression checks"): a mean over n trials, less another, divided by their standard error
// estimated from the trials' sd, is t-distributed; its tails are those of the normal
// distribution only for many trials.
#pragma once

namespace fss::student_t {

// The largest degrees of freedom used: beyond it the distribution is the normal one to better
// than 0.1 % in the quantiles used, and a larger value is treated as this one (a slightly larger
// quantile).
inline constexpr double kMaxDegreesOfFreedom = 1e4;

// P(|T| > t) for T Student-t with nu > 0 degrees of freedom.
double two_sided_tail(double t, double nu);

// The t >= 0 with two_sided_tail(t, nu) = p, for 0 < p <= 1.
double two_sided_quantile(double p, double nu);

}  // namespace fss::student_t
