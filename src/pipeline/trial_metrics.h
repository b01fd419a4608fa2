// The metrics of one trial's restoration and their statistics over the trials of a run
// (docs/method.md §5). Internal to the library.
#pragma once

#include "fss/core/image.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// RMSE, PSNR, RMSE_CI, PSNR_CI and SSIM of one restoration over the report's windows.
Metrics measure(const SimulationReport& report, const Image& input, const Image& restored);

// The sample standard deviation from the sum and the sum of squares of n values; 0 for n < 2.
double sample_sd(double sum, double sum_sq, int n);

// Sums of the trials' metrics, for their means and sample deviations.
struct TrialSums {
  double rmse = 0.0, rmse_sq = 0.0, ci = 0.0, ci_sq = 0.0, ssim = 0.0, ssim_sq = 0.0;
  bool has_ssim = true;

  void add(const Metrics& m);
  TrialStatistics statistics(int n) const;
};

// The warning of a run whose SSIM is null (no pixel left in its window).
void add_ssim_warning(SimulationReport& report);

}  // namespace fss
