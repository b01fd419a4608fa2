#include "fss/campaign/gaps.h"

#include <algorithm>
#include <set>
#include <string_view>

namespace fss {

namespace {

// The setting columns a gap may be told apart by, in the order they are shown.
constexpr std::string_view kSettingColumns[] = {
    "image", "code", "mode",       "velocity",    "velocity_distribution", "restore_velocity",
    "snr",   "dt",   "read_noise", "restoration", "regularization",        "prior"};

std::string shown_cell(std::string_view column, const std::string& cell) {
  if (column != "image") return cell;
  const std::size_t slash = cell.rfind('/');
  return slash == std::string::npos ? cell : cell.substr(slash + 1);
}

// Whether some row restores at a velocity other than its own (else restore_velocity repeats it).
bool restore_velocity_given(const std::vector<ResultRow>& rows) {
  const auto velocity = static_cast<std::size_t>(campaign_column_index("velocity"));
  const auto restore = static_cast<std::size_t>(campaign_column_index("restore_velocity"));
  return std::any_of(rows.begin(), rows.end(), [&](const ResultRow& row) {
    return restore < row.size() && !row[restore].empty() && row[restore] != row[velocity];
  });
}

// Indices of the setting columns whose value differs between rows (the code always).
std::vector<int> varying_columns(const std::vector<ResultRow>& rows) {
  std::vector<int> varying;
  const bool restore = restore_velocity_given(rows);
  for (std::string_view name : kSettingColumns) {
    if (name == "restore_velocity" && !restore) continue;
    const int at = campaign_column_index(name);
    std::set<std::string> values;
    for (const ResultRow& row : rows) {
      if (static_cast<std::size_t>(at) < row.size()) values.insert(row[at]);
    }
    if (values.size() > 1 || name == "code") varying.push_back(at);
  }
  return varying;
}

std::string setting_text(const ResultRow& row, const std::vector<int>& columns) {
  std::string text;
  for (const int at : columns) {
    const std::string_view name = campaign_columns(true)[at].name;
    if (static_cast<std::size_t>(at) >= row.size() || row[at].empty()) continue;
    if (!text.empty()) text += ' ';
    text += std::string(name) + "=" + shown_cell(name, row[at]);
  }
  return text;
}

// The distinct reasons of the gaps of one kind, in their first order.
std::vector<std::string> reasons_of(const std::vector<CampaignGap>& gaps, GapKind kind) {
  std::vector<std::string> reasons;
  for (const CampaignGap& g : gaps) {
    if (g.kind == kind && std::find(reasons.begin(), reasons.end(), g.message) == reasons.end()) {
      reasons.push_back(g.message);
    }
  }
  return reasons;
}

// The lines of the gaps of one kind: each reason once, then (for settings that cannot run) its
// settings, at most max_lines in all.
void add_reason_lines(const std::vector<CampaignGap>& gaps, GapKind kind, int max_lines,
                      std::vector<std::string>& lines) {
  int shown = 0;
  long long left_out = 0;
  for (const std::string& reason : reasons_of(gaps, kind)) {
    const auto of_reason = [&](const CampaignGap& g) {
      return g.kind == kind && g.message == reason;
    };
    if (kind == GapKind::kDoesNotApply) {
      // Expected of the product: each reason once, with its count.
      const auto count = std::count_if(gaps.begin(), gaps.end(), of_reason);
      lines.push_back("  " + reason + " (" + std::to_string(count) + " settings)");
      continue;
    }
    if (shown < max_lines) {
      lines.push_back("  " + reason + ":");
      ++shown;
    }
    for (const CampaignGap& g : gaps) {
      if (!of_reason(g)) continue;
      if (shown < max_lines) {
        lines.push_back("    " + g.setting);
        ++shown;
      } else {
        ++left_out;
      }
    }
  }
  if (left_out > 0) lines.push_back("  ... and " + std::to_string(left_out) + " more settings");
}

}  // namespace

std::vector<CampaignGap> campaign_gaps(const std::vector<ResultRow>& rows,
                                       bool with_distributions) {
  const auto status_at = static_cast<std::size_t>(campaign_column_index("status"));
  const auto message_at = static_cast<std::size_t>(campaign_column_index("message"));
  const std::size_t width = campaign_columns(with_distributions).size();
  const std::vector<int> columns = varying_columns(rows);
  std::vector<CampaignGap> gaps;
  for (const ResultRow& row : rows) {
    if (row.size() != width) continue;
    const std::string& status = row[status_at];
    if (status == kStatusOk || status == kStatusNotInvertible) continue;
    const GapKind kind =
        status == kStatusCodeRefused ? GapKind::kDoesNotApply : GapKind::kCannotRun;
    gaps.push_back({kind, setting_text(row, columns), status, row[message_at]});
  }
  return gaps;
}

long long count_gaps(const std::vector<CampaignGap>& gaps, GapKind kind) {
  return std::count_if(gaps.begin(), gaps.end(),
                       [kind](const CampaignGap& g) { return g.kind == kind; });
}

std::vector<std::string> gap_report_lines(const std::vector<CampaignGap>& gaps, long long total,
                                          int max_lines) {
  std::vector<std::string> lines;
  for (const GapKind kind : {GapKind::kCannotRun, GapKind::kDoesNotApply}) {
    const long long count = count_gaps(gaps, kind);
    if (count == 0) continue;
    lines.push_back(std::to_string(count) + " of " + std::to_string(total) + " settings " +
                    (kind == GapKind::kCannotRun
                         ? "cannot run (status too-narrow, invalid or failed in results.csv):"
                         : "do not apply (status code-refused in results.csv):"));
    add_reason_lines(gaps, kind, max_lines, lines);
  }
  return lines;
}

}  // namespace fss
