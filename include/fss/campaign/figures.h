// Figures of a campaign: for each swept quantity, RMSE against it with one
// curve per code (per code and restoration when the campaign has several
// restorations) and error bars, one figure per combination of the other
// settings; log axes for snr and geometric ranges.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fss/campaign/results.h"
#include "fss/campaign/spec.h"

namespace fss {

struct CampaignFigure {
  std::string name;  // file name without extension: rmse_vs_snr_1
  std::vector<std::uint8_t> png;
  std::string svg;
};

// Most figures campaign_figures draws, and most curves on one figure.
inline constexpr int kMaxCampaignFigures = 64;
inline constexpr int kMaxCurvesPerFigure = 8;
inline constexpr int kMaxCodesPerFigure = kMaxCurvesPerFigure;  // its earlier name

// The figures of a complete campaign's rows (in product order). Error bars
// are +/- one sample standard deviation of the trials; the title gives the
// fixed settings, the trials and the RMSE margin. Quantities with one value
// have no figure; beyond kMaxCampaignFigures the rest are left out, and
// curves beyond kMaxCurvesPerFigure start a new figure.
std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& campaign,
                                             const std::vector<ResultRow>& rows);

}  // namespace fss
