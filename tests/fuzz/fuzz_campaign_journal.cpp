// libFuzzer target: a campaign journal as `campaign merge` and a resumed
// run read it (campaign_journal::parse), then the campaign its header holds
// (campaign_from_canonical_json) and the result files its rows make. A
// runtime fss::Error of one short line is the expected end for bad bytes;
// any other exception, a crash, a sanitizer report, a long or multi-line
// message, a row outside its shard, a row line that does not read back the
// same, or a results.jsonl line that is not JSON is a bug.
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "campaign/journal.h"
#include "fss/campaign/results.h"
#include "fss/campaign/spec.h"
#include "fuzz_check.h"

namespace {

namespace journal = fss::campaign_journal;

constexpr std::size_t kMaxMessage = 400;

// Each line of `text` is a JSON object.
void check_jsonl(const std::string& text) {
  std::size_t begin = 0;
  while (begin < text.size()) {
    const std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) __builtin_trap();
    const nlohmann::json line =
        nlohmann::json::parse(text.substr(begin, end - begin), nullptr, false);
    if (!line.is_object()) __builtin_trap();
    begin = end + 1;
  }
}

// A header line holding what `c` read from one.
std::string header_of(const journal::Contents& c) {
  const nlohmann::json j = {{"fssim_campaign_journal", 1},
                            {"campaign_sha256", c.campaign_sha256},
                            {"shard", journal::shard_text(c.shard)},
                            {"settings", c.settings},
                            {"campaign", c.campaign_json}};
  return j.dump() + "\n";
}

// What a journal that parsed promises.
void check_contents(const journal::Contents& c) {
  if (c.valid_bytes > c.file_bytes) __builtin_trap();
  std::vector<fss::ResultRow> rows;
  for (const auto& [index, row] : c.rows) {
    if (index < 0 || index >= c.settings || index % c.shard.count != c.shard.index - 1) {
      __builtin_trap();
    }
    // A row line reads back as the same row.
    const journal::Contents again =
        journal::parse(header_of(c) + journal::row_line(index, row), "again");
    if (again.rows.size() != 1 || again.rows.begin()->second != row) __builtin_trap();
    rows.push_back(row);
  }
  check_jsonl(fss::results_jsonl(rows));
  fss::results_csv(rows);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  journal::Contents contents;
  try {
    contents = journal::parse(bytes, "fuzz/journal.jsonl");
  } catch (const fss::Error& e) {
    if (e.kind() != fss::ErrorKind::kRuntime) __builtin_trap();
    fss::fuzz::check_message(e, kMaxMessage);
    return 0;
  }
  check_contents(contents);
  try {
    const fss::ResolvedCampaign campaign =
        fss::campaign_from_canonical_json(contents.campaign_json);
    if (campaign.setting_count() < 1 || campaign.setting_count() > fss::kMaxCampaignSettings) {
      __builtin_trap();
    }
    // Every setting of the campaign has its place and description.
    const long long last = campaign.setting_count() - 1;
    for (const long long i : {0LL, last / 2, last}) {
      const fss::Setting s = fss::setting_at(campaign, i);
      fss::setting_description(campaign, s);
      fss::setting_options(campaign, s);
    }
  } catch (const fss::Error& e) {
    if (e.kind() != fss::ErrorKind::kRuntime) __builtin_trap();
    fss::fuzz::check_message(e, kMaxMessage);
  }
  return 0;
}
