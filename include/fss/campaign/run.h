// Running a campaign into a directory, resumably and in shards, and merging the shards
// (docs/campaign.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fss/campaign/results.h"
#include "fss/campaign/spec.h"

namespace fss {

// Part `index` of `count` (1-based): the settings whose product index i has
// i % count == index - 1.
struct CampaignShard {
  int index = 1;
  int count = 1;
};

// Parses "I/N" (1 <= I <= N); throws a usage fss::Error naming `text`.
CampaignShard parse_shard(const std::string& text);

struct CampaignProgress {
  long long done = 0;      // settings of the shard in the journal
  long long total = 0;     // settings of the shard
  long long resumed = 0;   // of `done`, those found in the journal at the start
  double elapsed_s = 0.0;  // since this run started
};

struct CampaignRunOptions {
  CampaignShard shard;
  int threads = 0;
  std::size_t max_memory_bytes = 0;
  std::string fssim_version;
  // Files the run reads besides the campaign's images, code files and velocity
  // files (the campaign file): none of them may be a file the run writes.
  std::vector<std::string> inputs;
  // Called after each setting (and once at the start); may be empty.
  std::function<void(const CampaignProgress&)> progress;

  bool IsValid(std::string* error) const;
};

struct CampaignRunSummary {
  long long total = 0;          // settings of the shard
  long long ran = 0;            // run by this call
  long long resumed = 0;        // found in the journal
  std::vector<ResultRow> rows;  // the shard's rows in product order
  // Kernels (SimulationPlan) computed and reused by this call.
  long long plans_built = 0;
  long long plans_reused = 0;
};

// Names of the files of a campaign directory.
inline constexpr const char* kCampaignJournal = "journal.jsonl";
inline constexpr const char* kCampaignResultsCsv = "results.csv";
inline constexpr const char* kCampaignResultsJsonl = "results.jsonl";
inline constexpr const char* kCampaignManifest = "campaign.json";
// With per_trial: one row per trial (trial_columns), settings in product order.
inline constexpr const char* kCampaignTrialsCsv = "trials.csv";
inline constexpr const char* kCampaignTrialsJsonl = "trials.jsonl";
// Largest journal read (checked before reading): some million settings.
inline constexpr std::size_t kMaxCampaignJournalBytes = std::size_t{2} << 30;

// Runs the settings of `options.shard` missing from dir's journal (dir is created if needed),
// journalling each as it ends so that a rerun resumes a killed run, then writes the result files,
// whose bytes depend only on the specification and the fssim version. Throws a usage fss::Error
// when dir holds another campaign or shard, or when a file it writes is one of its inputs (images,
// code files, velocity files, options.inputs), a runtime one when a file cannot be read or
// written or a setting fails at run time (the journal keeps what finished; a failed run before
// any setting finished leaves no directory it created).
CampaignRunSummary RunCampaign(const ResolvedCampaign& campaign, const std::string& dir,
                               const CampaignRunOptions& options);

// Merges the directories of the shards 1/N .. N/N of one campaign into dir, writing the files,
// journal included, a single-machine run leaves, byte for byte. Refuses (usage fss::Error) parts
// of different campaigns or N, a shard given twice or missing, a part whose journal lacks some of
// its settings, and an output file that is one of the parts' journals. Returns the rows in product
// order; *campaign (when not null) receives the campaign.
std::vector<ResultRow> MergeCampaignParts(const std::vector<std::string>& parts,
                                          const std::string& dir,
                                          ResolvedCampaign* campaign = nullptr);

// Writes `bytes` to path through a temporary file in the same directory,
// fsynced and renamed into place.
void write_file_durably(const std::string& path, const std::string& bytes);

}  // namespace fss
