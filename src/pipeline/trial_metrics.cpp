#include "pipeline/trial_metrics.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "fss/pipeline/metrics.h"
#include "pipeline/ssim.h"

namespace fss {

Metrics measure(const SimulationReport& report, const Image& input, const Image& restored) {
  const int offset = report.output_first_column();
  Metrics m;
  m.rmse = rmse(input, offset, restored, report.rmse_first, report.rmse_end);
  m.psnr = psnr(m.rmse);
  m.rmse_ci = rmse_contrast_invariant(input, offset, restored, report.rmse_ci_first,
                                      report.rmse_ci_end, report.options.threads);
  m.psnr_ci = psnr(m.rmse_ci);
  m.ssim = structural_similarity(input, offset, restored, report.rmse_first, report.rmse_end,
                                 report.options.threads);
  return m;
}

double sample_sd(double sum, double sum_sq, int n) {
  if (n < 2) return 0.0;
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)));
}

void TrialSums::add(const Metrics& m) {
  rmse += m.rmse;
  rmse_sq += m.rmse * m.rmse;
  ci += m.rmse_ci;
  ci_sq += m.rmse_ci * m.rmse_ci;
  has_ssim = has_ssim && m.ssim.has_value();
  if (m.ssim) ssim += *m.ssim, ssim_sq += *m.ssim * *m.ssim;
}

TrialStatistics TrialSums::statistics(int n) const {
  TrialStatistics t{n,
                    rmse / n,
                    sample_sd(rmse, rmse_sq, n),
                    ci / n,
                    sample_sd(ci, ci_sq, n),
                    std::nullopt,
                    std::nullopt,
                    std::nullopt,
                    std::nullopt};
  if (has_ssim) t.ssim_mean = ssim / n, t.ssim_sd = sample_sd(ssim, ssim_sq, n);
  return t;
}

void add_ssim_warning(SimulationReport& report) {
  if (report.metrics.ssim) return;
  report.warnings.push_back(
      "SSIM is null: it is taken over the RMSE window, which must start at least 5 columns "
      "inside the output (a margin of 5 or more) on an image of at least 11 rows, so that each "
      "pixel's 11 x 11 window lies inside it (docs/method.md §5)");
}

}  // namespace fss
