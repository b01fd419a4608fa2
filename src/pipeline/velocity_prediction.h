// The predicted error of a run under a velocity distribution (docs/method.md §13): the exact
// expected MSE at each velocity (§6b) on the run's one geometry, averaged over the distribution
// by adaptive quadrature. Internal to the library.
#pragma once

#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/simulate.h"

namespace fss {

class PlanCore;

// The prediction of the run `report` describes (its options with a velocity distribution, code,
// geometry and windows; `plan` its PlanCore) on `input`:
//   mse = E_V[ RMSE_0(V)^2 + sum_j W_V(j) S_V(j) / count ]
// by expected_over_velocity to `relative_tolerance` within `max_intervals`, starting from
// kDesignVelocityPanels equal intervals (so that the first estimates see the integrand's
// wiggles), where at each velocity v a noise-free pass observes at v and restores at v (or the
// restore velocity) on the run's geometry (RMSE_0(v), S_v(j)) and W_v(j) is the filter's. The
// other fields are averaged at the quadrature's final nodes and weights (prediction.h). Infinite,
// without any pass, when the inverse filter meets a kernel that is not invertible: at the restore
// velocity, or at an end of the support (min |K| over the band |xi| <= pi depends on v only
// through |v| dt, and falls as |v| grows). Adds to `warnings` when some velocity's readouts clip
// or the quadrature did not converge.
Prediction predict_over_velocities(const PlanCore& plan, const SimulationReport& report,
                                   const Image& input, const ShutterCode& code,
                                   double relative_tolerance, std::vector<std::string>* warnings,
                                   int max_intervals = kMaxVelocityQuadratureIntervals);

}  // namespace fss
