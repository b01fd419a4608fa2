#include "fss/campaign/run.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "campaign/journal.h"
#include "fss/campaign/sha256.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"

namespace fss {

namespace fs = std::filesystem;
namespace journal = campaign_journal;

CampaignShard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  CampaignShard shard{0, 0};
  try {
    std::size_t used_i = 0, used_n = 0;
    if (slash != std::string::npos) {
      shard.index = std::stoi(text.substr(0, slash), &used_i);
      shard.count = std::stoi(text.substr(slash + 1), &used_n);
    }
    if (slash == std::string::npos || used_i != slash || used_n != text.size() - slash - 1) {
      shard = {0, 0};
    }
  } catch (const std::exception&) {
    shard = {0, 0};
  }
  if (!(shard.count >= 1 && shard.index >= 1 && shard.index <= shard.count)) {
    throw_usage_error("shard '" + escape_control_characters(text) +
                      "': expected I/N with 1 <= I <= N, such as 2/4");
  }
  return shard;
}

bool CampaignRunOptions::IsValid(std::string* error) const {
  if (shard.count >= 1 && shard.index >= 1 && shard.index <= shard.count) return true;
  if (error) *error = "shard = " + journal::shard_text(shard) + ": must be I/N with 1 <= I <= N";
  return false;
}

void write_file_durably(const std::string& path, const std::string& bytes) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string temp_name = ".";
  temp_name += target.filename().string();
  temp_name += ".tmp";
  const std::string temp = (dir / temp_name).string();
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  bool ok = fd >= 0;
  std::size_t written = 0;
  while (ok && written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) written += static_cast<std::size_t>(n);
  }
  const int saved = errno;
  ok = ok && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
    std::error_code ec;
    fs::remove(temp, ec);
    throw_runtime_error("cannot write '" + escape_control_characters(path) +
                        "': " + std::strerror(saved ? saved : errno));
  }
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

namespace {

std::string manifest(const ResolvedCampaign& campaign, const CampaignShard& shard) {
  const nlohmann::json j = {{"schema_version", kCampaignSchemaVersion},
                            {"campaign_sha256", campaign.sha256},
                            {"settings", campaign.setting_count()},
                            {"shard", journal::shard_text(shard)},
                            {"campaign", nlohmann::json::parse(campaign.canonical_json)}};
  return j.dump(2) + "\n";
}

// The rows of the settings in `contents` (index order) and, for a campaign
// with per_trial, their trial rows, written into dir.
void write_results(const std::string& dir, const ResolvedCampaign& campaign,
                   const CampaignShard& shard, const journal::Contents& contents,
                   std::vector<ResultRow>* rows_out) {
  std::vector<ResultRow> rows;
  std::vector<ResultRow> trial_rows;
  for (const auto& [index, row] : contents.rows) {
    rows.push_back(row);
    const auto trials = contents.trial_rows.find(index);
    if (trials == contents.trial_rows.end()) continue;
    trial_rows.insert(trial_rows.end(), trials->second.begin(), trials->second.end());
  }
  if (campaign.per_trial) {
    write_file_durably((fs::path(dir) / kCampaignTrialsCsv).string(), trials_csv(trial_rows));
    write_file_durably((fs::path(dir) / kCampaignTrialsJsonl).string(), trials_jsonl(trial_rows));
  }
  write_file_durably((fs::path(dir) / kCampaignResultsCsv).string(), results_csv(rows));
  write_file_durably((fs::path(dir) / kCampaignResultsJsonl).string(), results_jsonl(rows));
  write_file_durably((fs::path(dir) / kCampaignManifest).string(), manifest(campaign, shard));
  if (rows_out != nullptr) *rows_out = std::move(rows);
}

std::string short_hash(const std::string& sha256) { return sha256.substr(0, 12); }

// The journal of dir for this campaign and shard: read (refusing another
// campaign or shard) or started.
journal::Contents open_journal(const ResolvedCampaign& campaign, const std::string& dir,
                               const CampaignShard& shard) {
  const std::string path = (fs::path(dir) / kCampaignJournal).string();
  std::optional<journal::Contents> contents = journal::read(path);
  if (!contents) {
    write_file_durably(path, journal::header_line(campaign, shard));
    contents = journal::read(path);
  }
  if (contents->campaign_sha256 != campaign.sha256) {
    throw_usage_error("'" + escape_control_characters(dir) + "' holds another campaign (" +
                      short_hash(contents->campaign_sha256) + ", see its " + kCampaignJournal +
                      ") than this specification (" + short_hash(campaign.sha256) +
                      "): the images, codes or values changed; use a new output directory");
  }
  if (contents->shard.index != shard.index || contents->shard.count != shard.count) {
    throw_usage_error("'" + escape_control_characters(dir) + "' holds shard " +
                      journal::shard_text(contents->shard) + " of this campaign, not shard " +
                      journal::shard_text(shard) + "; use one directory per shard");
  }
  return *contents;
}

// Decodes image `i` of the campaign, checking that the file still has the
// digest the campaign was made with.
Image load_image(const ResolvedCampaign& campaign, int i) {
  const CampaignImage& image = campaign.images[i];
  std::ifstream in(image.path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) {
    throw_runtime_error("cannot read image '" + escape_control_characters(image.path) + "'");
  }
  const std::string data = bytes.str();
  if (sha256_hex(data) != image.sha256) {
    throw_runtime_error("image '" + escape_control_characters(image.path) +
                        "' changed since the campaign started (its SHA-256 differs)");
  }
  return decode_png(reinterpret_cast<const std::uint8_t*>(data.data()), data.size(), image.path);
}

// An exclusive lock on DIR/.campaign.lock for the life of the object: two
// runs into one directory would both append to its journal. The kernel
// releases it when the process dies, kill -9 included.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& dir) {
    const std::string path = (fs::path(dir) / ".campaign.lock").string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      throw_runtime_error("cannot create '" + escape_control_characters(path) +
                          "': " + std::strerror(errno));
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      throw_usage_error("'" + escape_control_characters(dir) +
                        "' is in use by another fssim campaign run; wait for it or use another "
                        "directory");
    }
  }
  ~DirectoryLock() { ::close(fd_); }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace

CampaignRunSummary RunCampaign(const ResolvedCampaign& campaign, const std::string& dir,
                               const CampaignRunOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) {
    throw_runtime_error("cannot create the campaign directory '" + escape_control_characters(dir) +
                        "'");
  }
  const DirectoryLock lock(dir);
  journal::Contents contents = open_journal(campaign, dir, options.shard);
  const auto start = std::chrono::steady_clock::now();
  const long long settings = campaign.setting_count();
  CampaignRunSummary summary;
  summary.total = journal::shard_size(settings, options.shard);
  summary.resumed = static_cast<long long>(contents.rows.size());
  CampaignProgress progress{summary.resumed, summary.total, summary.resumed, 0.0};
  if (options.progress) options.progress(progress);
  const SettingRunOptions run_options{options.threads, options.max_memory_bytes,
                                      options.fssim_version};
  journal::Appender appender((fs::path(dir) / kCampaignJournal).string(), contents.valid_bytes);
  int loaded = -1;  // settings are image-major: each image is decoded once
  Image image;
  SimulationPlanCache plans;  // each kernel once per code, mode, velocities, dt and width
  std::vector<ResultRow> trial_rows;
  std::vector<ResultRow>* trials = campaign.per_trial ? &trial_rows : nullptr;
  for (long long i = options.shard.index - 1; i < settings; i += options.shard.count) {
    if (contents.rows.count(i)) continue;
    const Setting setting = setting_at(campaign, i);
    if (setting.image != loaded) {
      image = load_image(campaign, setting.image);
      loaded = setting.image;
    }
    ResultRow row = run_setting(campaign, setting, image, run_options, &plans, trials);
    appender.append(journal::row_line(i, row, trials));
    if (trials != nullptr) contents.trial_rows[i] = std::exchange(trial_rows, {});
    contents.rows[i] = std::move(row);
    ++summary.ran;
    progress.done = static_cast<long long>(contents.rows.size());
    progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.progress) options.progress(progress);
  }
  appender.finish();
  summary.plans_built = plans.built();
  summary.plans_reused = plans.reused();
  write_results(dir, campaign, options.shard, contents, &summary.rows);
  return summary;
}

namespace {

struct Part {
  std::string dir;
  journal::Contents contents;
};

Part read_part(const std::string& dir) {
  const std::string path = (fs::path(dir) / kCampaignJournal).string();
  std::optional<journal::Contents> contents = journal::read(path);
  if (!contents) {
    throw_usage_error("part '" + escape_control_characters(dir) +
                      "' is not a campaign directory (no " + kCampaignJournal + ")");
  }
  return {dir, std::move(*contents)};
}

void check_parts(const std::vector<Part>& parts) {
  const journal::Contents& first = parts.front().contents;
  std::set<int> seen;
  for (const Part& part : parts) {
    const journal::Contents& c = part.contents;
    const std::string name = "part '" + escape_control_characters(part.dir) + "'";
    if (c.campaign_sha256 != first.campaign_sha256) {
      throw_usage_error(name + " belongs to campaign " + short_hash(c.campaign_sha256) + ", '" +
                        escape_control_characters(parts.front().dir) + "' to campaign " +
                        short_hash(first.campaign_sha256) + ": they cannot be merged");
    }
    if (c.shard.count != first.shard.count) {
      throw_usage_error(name + " is shard " + journal::shard_text(c.shard) + ", but '" +
                        escape_control_characters(parts.front().dir) + "' is shard " +
                        journal::shard_text(first.shard) +
                        ": the parts split the work differently");
    }
    if (!seen.insert(c.shard.index).second) {
      throw_usage_error(name + " is shard " + journal::shard_text(c.shard) +
                        ", given more than once");
    }
    const long long expected = journal::shard_size(c.settings, c.shard);
    if (static_cast<long long>(c.rows.size()) != expected) {
      throw_usage_error(name + " (shard " + journal::shard_text(c.shard) + ") is incomplete: " +
                        std::to_string(c.rows.size()) + " of " + std::to_string(expected) +
                        " settings done; run its command again to finish it");
    }
  }
  for (int i = 1; i <= first.shard.count; ++i) {
    if (!seen.count(i)) {
      throw_usage_error("shard " + journal::shard_text({i, first.shard.count}) +
                        " is missing from the parts");
    }
  }
}

}  // namespace

std::vector<ResultRow> MergeCampaignParts(const std::vector<std::string>& part_dirs,
                                          const std::string& dir, ResolvedCampaign* out) {
  if (part_dirs.empty()) throw_usage_error("campaign merge needs at least one part");
  std::vector<Part> parts;
  std::error_code ec;
  for (const std::string& part : part_dirs) {
    if (fs::equivalent(part, dir, ec)) {
      throw_usage_error("the merge output '" + escape_control_characters(dir) +
                        "' must not be one of the parts");
    }
    parts.push_back(read_part(part));
  }
  check_parts(parts);
  const ResolvedCampaign campaign =
      campaign_from_canonical_json(parts.front().contents.campaign_json);
  if (campaign.sha256 != parts.front().contents.campaign_sha256) {
    throw_runtime_error("part '" + escape_control_characters(parts.front().dir) +
                        "': its journal's specification does not match its hash");
  }
  journal::Contents merged;
  for (Part& part : parts) {
    merged.rows.merge(part.contents.rows);
    merged.trial_rows.merge(part.contents.trial_rows);
  }
  std::string journal_text = journal::header_line(campaign, {1, 1});
  for (const auto& [index, row] : merged.rows) {
    const auto trials = merged.trial_rows.find(index);
    journal_text += journal::row_line(
        index, row, trials == merged.trial_rows.end() ? nullptr : &trials->second);
  }
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) {
    throw_runtime_error("cannot create the merge output '" + escape_control_characters(dir) + "'");
  }
  if (const auto existing = journal::read((fs::path(dir) / kCampaignJournal).string())) {
    if (existing->campaign_sha256 != campaign.sha256) {
      throw_usage_error("'" + escape_control_characters(dir) + "' holds another campaign (" +
                        short_hash(existing->campaign_sha256) + "); use a new output directory");
    }
  }
  write_file_durably((fs::path(dir) / kCampaignJournal).string(), journal_text);
  std::vector<ResultRow> ordered;
  write_results(dir, campaign, {1, 1}, merged, &ordered);
  if (out) *out = campaign;
  return ordered;
}

}  // namespace fss
