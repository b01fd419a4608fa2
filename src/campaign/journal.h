// The journal of a campaign directory (fss/campaign/run.h): reading it,
// starting it, appending a setting's row durably.
#pragma once

#include <future>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "fss/campaign/results.h"
#include "fss/campaign/run.h"

namespace fss {

// The first setting column (image, code, mode, velocity, ..., trials) in
// which `row` differs from setting `index` of `c`, "" when it is that
// setting's row (src/campaign/results.cpp).
std::string row_setting_mismatch(const ResolvedCampaign& c, long long index, const ResultRow& row);

// A row (a trial row when `trial`) of results schema 2, as an fssim before the restorations
// journalled it, in the present columns: its cells where it has them, the restoration "inverse",
// the other cells (SSIM, the restoration's) empty; nullopt when `row` does not have schema 2's
// width (src/campaign/results.cpp).
std::optional<ResultRow> upgrade_schema2_row(const ResultRow& row, bool trial);

}  // namespace fss

namespace fss::campaign_journal {

struct Contents {
  std::string campaign_json;  // canonical specification
  std::string campaign_sha256;
  CampaignShard shard;
  long long settings = 0;  // of the whole campaign
  std::map<long long, ResultRow> rows;
  // A campaign with per_trial: the trial rows of each setting in `rows`.
  std::map<long long, std::vector<ResultRow>> trial_rows;
  std::size_t valid_bytes = 0;  // up to the last complete line
  std::size_t file_bytes = 0;
};

// The journal at `path`, or nullopt when there is none. Throws a runtime
// fss::Error, and touches nothing, for a journal larger than
// kMaxCampaignJournalBytes, a directory or anything else not a journal, and
// a corrupt line (parse).
std::optional<Contents> read(const std::string& path);

// The journal whose bytes are `bytes` (`path` names it in messages). Refuses
// (a runtime fss::Error naming `path` and the line) bytes without a complete
// header line (the header is written whole, renamed into place: such a file
// is not fssim's), a malformed header or row line, JSON nested deeper than
// campaign_input::kMaxJsonDepth, a row whose index is outside the campaign
// or belongs to another shard, and a row whose cells do not fit their
// columns. A last line without its newline is torn: left out of `rows` and
// `valid_bytes`.
Contents parse(std::string_view bytes, const std::string& path);

// The header line of a journal (newline included).
std::string header_line(const ResolvedCampaign& campaign, const CampaignShard& shard);
// The line of one finished setting (newline included); with `trial_rows`
// (a campaign with per_trial), its trial rows too.
std::string row_line(long long index, const ResultRow& row,
                     const std::vector<ResultRow>* trial_rows = nullptr);

// Appends lines to a journal. Each line is written at once (a killed
// process loses none) and fsynced on a helper thread while the caller goes
// on with the next setting; append() waits for the previous line's fsync
// before writing, so every line is on disk before the next one is written,
// and finish() waits for the last.
class Appender {
 public:
  // Opens `path`, first cutting it to `valid_bytes` (a torn last line).
  Appender(const std::string& path, std::size_t valid_bytes);
  ~Appender();
  Appender(const Appender&) = delete;
  Appender& operator=(const Appender&) = delete;
  void append(const std::string& line);
  // Waits for the last fsync; throws a runtime fss::Error if one failed.
  void finish();

 private:
  std::string path_;
  int fd_ = -1;
  std::future<int> sync_;  // errno of the pending fdatasync, 0 on success
};

// "1/4".
std::string shard_text(const CampaignShard& shard);

// Number of settings of `shard` in a campaign of `settings` settings.
long long shard_size(long long settings, const CampaignShard& shard);

}  // namespace fss::campaign_journal
