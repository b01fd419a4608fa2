// The restorations whose filter depends on the image (docs/method.md §12): Wiener with the
// oracle prior (the ground truth's spectrum), Wiener with a power-law prior fitted to a
// calibration observation, and Tikhonov at the lambda that minimises the run's exact expected
// error. Each is fitted once per run, then fixed for every trial, so the restoration stays linear
// and its exact prediction holds for the filter fitted. Internal to the library.
#pragma once

#include <optional>
#include <vector>

#include "fss/core/image.h"
#include "fss/pipeline/simulate.h"
#include "pipeline/restore.h"

namespace fss {

class PlanCore;

// The calibration observation's random streams: channel coordinate kCalibrationChannel + c of
// the run's seed, which no trial uses (trials use the channels 0 .. C - 1).
inline constexpr int kCalibrationChannel = 1 << 30;

struct FittedFilter {
  std::optional<RowRestorer> restorer;
  double m_amplification = 0.0;       // mean |H|^2 on the grid
  std::vector<double> noise_weights;  // W(j), empty without noise
  RestorationSummary summary;
};

// The filter of `options.restoration` for this run of `code` on `input` (the plan holds no
// restorer).
FittedFilter fit_restoration(const PlanCore& plan, const SimulationOptions& options,
                             const Image& input, const ShutterCode& code);

// The bytes fit_restoration holds beyond the plan for a run on a width x height x channels image:
// the noise-free observed crops of the Tikhonov search, the rows' statistics.
std::size_t fitted_restoration_bytes(const SimulationOptions& options, int observed_width,
                                     int height, int channels);

}  // namespace fss
