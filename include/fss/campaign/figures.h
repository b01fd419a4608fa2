// Figures of a campaign: for each swept quantity, RMSE against it with one
// curve per code and error bars, one figure per combination of the other
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

// Most figures campaign_figures draws, and most codes on one figure.
inline constexpr int kMaxCampaignFigures = 64;
inline constexpr int kMaxCodesPerFigure = 8;

// The figures of a complete campaign's rows (in product order). Error bars
// are +/- one sample standard deviation of the trials; the title gives the
// fixed settings, the trials and the RMSE margin. Quantities with one value
// have no figure; beyond kMaxCampaignFigures the rest are left out, and
// codes beyond kMaxCodesPerFigure start a new figure.
std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& campaign,
                                             const std::vector<ResultRow>& rows);

}  // namespace fss
