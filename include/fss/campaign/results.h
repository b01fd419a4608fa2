// The rows of a campaign (docs/campaign.md, "Results schema"): one row per
// setting, as text cells in the schema's column order, and their CSV and
// JSON Lines forms.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "fss/campaign/spec.h"
#include "fss/core/image.h"

namespace fss {

// Version of the results schema: the columns below, their order and meaning.
inline constexpr int kCampaignSchemaVersion = 2;

enum class ColumnKind { kText, kNumber, kBoolean };

struct ResultColumn {
  const char* name;
  ColumnKind kind;
};

// The columns of results.csv and results.jsonl, in order.
const std::vector<ResultColumn>& campaign_columns();
// Index of a column by name; -1 if there is none.
int campaign_column_index(std::string_view name);

// One row: campaign_columns().size() cells. Numbers are in shortest
// round-trip form ("inf" where a prediction is infinite), empty where the
// setting has no value.
using ResultRow = std::vector<std::string>;

// Row status values.
inline constexpr const char* kStatusOk = "ok";
inline constexpr const char* kStatusNotInvertible = "not-invertible";
inline constexpr const char* kStatusInvalid = "invalid";           // an option out of range
inline constexpr const char* kStatusCodeRefused = "code-refused";  // the mode cannot use the code
inline constexpr const char* kStatusTooNarrow = "too-narrow";      // image too narrow for the blur
inline constexpr const char* kStatusFailed = "failed";             // Simulate refused it otherwise

// What run_setting needs besides the setting.
struct SettingRunOptions {
  int threads = 0;                   // SimulationOptions::threads
  std::size_t max_memory_bytes = 0;  // SimulationOptions::max_memory_bytes
  std::string fssim_version;         // the fssim_version column
};

// Runs `setting` of `campaign` on `image` (the setting's image, decoded)
// with fss::Simulate and returns its row. A setting that cannot run is a
// row with its status and message; runtime and memory-limit errors are
// thrown as fss::Error.
ResultRow run_setting(const ResolvedCampaign& campaign, const Setting& setting, const Image& image,
                      const SettingRunOptions& options);

// results.csv: the header line, then one line per row.
std::string results_csv(const std::vector<ResultRow>& rows);
// results.jsonl: one JSON object per row, keys in column order; numbers as
// JSON numbers (null when empty or not finite), booleans as true/false.
std::string results_jsonl(const std::vector<ResultRow>& rows);

}  // namespace fss
