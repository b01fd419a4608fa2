// The rows of a campaign (docs/campaign.md, "Results schema"): one row per
// setting, as text cells in the schema's column order, and their CSV and
// JSON Lines forms.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fss/campaign/spec.h"
#include "fss/core/image.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// Version of the results schema: the columns below, their order and meaning. Version 3 added
// the restoration (restoration, regularization, prior, regularization_applied, prior_level,
// noise_variance) and SSIM (ssim_mean, ssim_sd; ssim in the trial rows).
inline constexpr int kCampaignSchemaVersion = 3;
// Version 4 adds, after the columns of version 3, the velocity distribution (docs/method.md §13):
// velocity_distribution, mse_mean, mse_sd and predicted_mse (velocity_distribution and
// trial_velocity in the trial rows). Only a campaign with velocity distributions has them and
// is version 4; any other keeps version 3, its columns and its bytes.
inline constexpr int kCampaignDistributionSchemaVersion = 4;

enum class ColumnKind { kText, kNumber, kBoolean };

struct ResultColumn {
  const char* name;
  ColumnKind kind;
};

// The columns of results.csv and results.jsonl, in order: of schema 3 (a campaign without
// velocity distributions), or of schema 4 (with them: the same, then velocity_distribution,
// mse_mean, mse_sd, predicted_mse).
const std::vector<ResultColumn>& campaign_columns();
const std::vector<ResultColumn>& campaign_columns(bool with_distributions);
// Index of a column by name (schema 4's names included; schema 3's columns are its first ones);
// -1 if there is none.
int campaign_column_index(std::string_view name);

// The columns of trials.csv and trials.jsonl (a campaign with per_trial): the setting columns of
// results.csv (image to trials), then trial (0, 1, ...), trial_seed (seed + trial), rmse, rmse_ci,
// psnr and ssim of that trial; with velocity distributions, then velocity_distribution and
// trial_velocity (the velocity the trial observed).
const std::vector<ResultColumn>& trial_columns();
const std::vector<ResultColumn>& trial_columns(bool with_distributions);

// One row: campaign_columns(with_distributions).size() cells; numbers in shortest round-trip form
// ("inf" where a prediction is infinite), empty where the setting has no value (the velocity
// under a distribution, the restore velocity too unless given).
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
  // Every setting with this seed instead of its own (setting_seed): fssim sweep's rule. Never set
  // by a campaign run.
  std::optional<std::uint64_t> seed = std::nullopt;
};

// The plans (fss::SimulationPlan) of the settings a run goes through, kept while they fit in
// kMaxBytes and kMaxPlans, so that each kernel is computed once, not once per snr value. Safe to
// share between threads: a plan is looked up, and built when missing, under the cache's lock, so
// each plan is built once whatever the number of threads.
class SimulationPlanCache {
 public:
  static constexpr std::size_t kMaxBytes = std::size_t{256} << 20;
  static constexpr std::size_t kMaxPlans = 4096;

  // A kept plan that fits the run, or a new one (oldest plans dropped
  // beyond the limits); it lives as long as the pointer. Throws what
  // SimulationPlan's constructor throws.
  std::shared_ptr<const SimulationPlan> share(const SimulationOptions& options, int width,
                                              const ShutterCode& code);
  // The same plan, valid until the next call from any thread.
  const SimulationPlan& plan(const SimulationOptions& options, int width, const ShutterCode& code);
  long long built() const;
  long long reused() const;

 private:
  mutable std::mutex mutex_;
  std::deque<std::shared_ptr<const SimulationPlan>> plans_;
  std::size_t bytes_ = 0;
  long long built_ = 0;
  long long reused_ = 0;
};

// Runs `setting` of `campaign` on `image` (the setting's image, decoded) with fss::Simulate and
// returns its row. A setting that cannot run is a row with its status and message; runtime and
// memory-limit errors are thrown. With `plans`, the kernel part comes from (and goes to) that
// cache: the row is the same. `trial_rows`, when not null, receives the setting's trial rows
// (trial_columns; none for a setting that did not run).
ResultRow run_setting(const ResolvedCampaign& campaign, const Setting& setting, const Image& image,
                      const SettingRunOptions& options, SimulationPlanCache* plans = nullptr,
                      std::vector<ResultRow>* trial_rows = nullptr);

// results.csv: the header line, then one line per row (of campaign_columns(with_distributions)).
std::string results_csv(const std::vector<ResultRow>& rows, bool with_distributions = false);
// results.jsonl: one JSON object per row, keys in column order; numbers as
// JSON numbers (null when empty or not finite), booleans as true/false.
std::string results_jsonl(const std::vector<ResultRow>& rows, bool with_distributions = false);

// trials.csv and trials.jsonl: the same forms with trial_columns(with_distributions).
std::string trials_csv(const std::vector<ResultRow>& rows, bool with_distributions = false);
std::string trials_jsonl(const std::vector<ResultRow>& rows, bool with_distributions = false);

}  // namespace fss
