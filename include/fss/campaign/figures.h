// Figures of a campaign: for each swept quantity, RMSE against it with one
// series per code (per code and restoration when the campaign has several
// restorations), the measured points with their error bars and the predicted
// curve, one figure per combination of the other settings; log axes for snr
// and geometric ranges. docs/campaign.md, "Figures".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fss/campaign/results.h"
#include "fss/campaign/spec.h"
#include "fss/io/plot.h"

namespace fss {

struct CampaignFigure {
  std::string name;  // file name without extension: rmse_vs_snr__camera__numerical__v0.5
  std::vector<std::uint8_t> png;
  std::string svg;
};

// Most figures campaign_figures draws, and most curves on one figure.
inline constexpr int kMaxCampaignFigures = 64;
inline constexpr int kMaxCurvesPerFigure = 8;
inline constexpr int kMaxCodesPerFigure = kMaxCurvesPerFigure;  // its earlier name

// A figure of a campaign before it is drawn: its name, title and data.
struct CampaignFigureData {
  std::string name;
  std::string title;
  MeasuredFigure figure;
};

// The figures of a complete campaign's rows (in product order), none
// without a point; named by what they hold (rmse_vs_snr__camera__numerical__v0.5).
std::vector<CampaignFigureData> campaign_figure_data(const ResolvedCampaign& campaign,
                                                     const std::vector<ResultRow>& rows);

// campaign_figure_data drawn, 800 x 500 pixels.
std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& campaign,
                                             const std::vector<ResultRow>& rows);

}  // namespace fss
