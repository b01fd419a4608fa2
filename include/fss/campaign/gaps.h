// The settings of a campaign that did not run, from its rows (results.h): those that cannot run
// (an image too narrow for the blur, an option out of range, a refusal of the simulation) and
// those the campaign's product makes but that do not apply (a mode that cannot use the code,
// such as an analog run of gains outside [0, 1]). docs/campaign.md, "Settings that do not run".
#pragma once

#include <string>
#include <vector>

#include "fss/campaign/results.h"

namespace fss {

enum class GapKind {
  kCannotRun,     // status too-narrow, invalid or failed: a gap in the results
  kDoesNotApply,  // status code-refused: expected of the product, not a gap
};

struct CampaignGap {
  GapKind kind = GapKind::kCannotRun;
  std::string setting;  // the values that tell it from the other rows: "code=raskar snr=25"
  std::string status;
  std::string message;
};

// The rows of `rows` (campaign_columns(with_distributions)) that did not run, in their order.
std::vector<CampaignGap> campaign_gaps(const std::vector<ResultRow>& rows,
                                       bool with_distributions = false);

// How many of `gaps` are of `kind`.
long long count_gaps(const std::vector<CampaignGap>& gaps, GapKind kind);

// Lines for a person (no trailing newline): a heading per kind, then each reason once: for the
// settings that cannot run followed by its settings, one line each (the setting columns that
// vary), at most `max_lines` in all and then "... and N more settings"; for those that do not
// apply with its count. Empty when there is no gap.
std::vector<std::string> gap_report_lines(const std::vector<CampaignGap>& gaps, long long total,
                                          int max_lines = 20);

}  // namespace fss
