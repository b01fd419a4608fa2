#include "fss/campaign/run.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "campaign/journal.h"
#include "campaign/sha256.h"
#include "campaign/user_input.h"
#include "core/parallel.h"
#include "fss/core/error.h"
#include "fss/io/image_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/memory_estimate.h"
#include "io/created_directories.h"
#include "io/safe_write.h"

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

namespace {

// Writes `bytes` to `fd`, fsyncs and closes it: 0 or the errno.
int write_sync_close(int fd, const std::string& bytes) {
  int error = 0;
  for (std::size_t written = 0; error == 0 && written < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) error = n < 0 ? errno : ENOSPC;
    if (n > 0) written += static_cast<std::size_t>(n);
  }
  if (error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  return error;
}

}  // namespace

void write_file_durably(const std::string& path, const std::string& bytes) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // A new temporary named for this process (O_EXCL: never a file already
  // there, nor one a symbolic link points to).
  static std::atomic<unsigned> counter{0};
  std::string temp;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    std::string name = ".";
    name += target.filename().string();
    name += ".fssim-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".tmp";
    temp = (dir / name).string();
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 && errno != EEXIST) break;
  }
  int error = fd < 0 ? errno : write_sync_close(fd, bytes);
  if (fd >= 0 && error == 0 && std::rename(temp.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    if (fd >= 0) ::unlink(temp.c_str());  // created above: ours
    throw_runtime_error("cannot write '" + escape_control_characters(path) +
                        "': " + std::strerror(error));
  }
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

namespace {

constexpr const char* kLockName = ".campaign.lock";

std::string manifest(const ResolvedCampaign& campaign, const CampaignShard& shard) {
  const int schema = campaign.has_velocity_distributions() ? kCampaignDistributionSchemaVersion
                                                           : kCampaignSchemaVersion;
  const nlohmann::json j = {{"schema_version", schema},
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
  const bool wide = campaign.has_velocity_distributions();
  const auto path = [&dir](const char* name) { return (fs::path(dir) / name).string(); };
  if (campaign.per_trial) {
    write_file_durably(path(kCampaignTrialsCsv), trials_csv(trial_rows, wide));
    write_file_durably(path(kCampaignTrialsJsonl), trials_jsonl(trial_rows, wide));
  }
  write_file_durably(path(kCampaignResultsCsv), results_csv(rows, wide));
  write_file_durably(path(kCampaignResultsJsonl), results_jsonl(rows, wide));
  write_file_durably(path(kCampaignManifest), manifest(campaign, shard));
  if (rows_out != nullptr) *rows_out = std::move(rows);
}

std::string short_hash(const std::string& sha256) {
  return escape_control_characters(sha256.substr(0, 12));
}

std::string shown_path(const std::string& path) {
  std::string shown = "'";
  shown += escape_control_characters(path);
  return shown + "'";
}

// Refuses a journal at `path` holding a row that is not its index's setting.
void check_rows_are_their_settings(const ResolvedCampaign& campaign,
                                   const journal::Contents& contents, const std::string& path) {
  for (const auto& [index, row] : contents.rows) {
    const std::string column = row_setting_mismatch(campaign, index, row);
    if (!column.empty()) {
      throw_runtime_error("campaign journal " + shown_path(path) + ": the row of setting " +
                          std::to_string(index) + " is not that setting's (its " + column +
                          " differs)");
    }
  }
  // Trial rows of the other schema (with or without velocity distributions) are not its.
  const std::size_t width = trial_columns(campaign.has_velocity_distributions()).size();
  for (const auto& [index, trials] : contents.trial_rows) {
    for (const ResultRow& trial : trials) {
      if (trial.size() != width) {
        throw_runtime_error("campaign journal " + shown_path(path) + ": a trial row of setting " +
                            std::to_string(index) + " is not that setting's (its " +
                            "velocity_distribution differs)");
      }
    }
  }
}

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
    throw_usage_error(shown_path(dir) + " holds another campaign (" +
                      short_hash(contents->campaign_sha256) + ", see its " + kCampaignJournal +
                      ") than this specification (" + short_hash(campaign.sha256) +
                      "): the images, codes or values changed; use a new output directory");
  }
  if (contents->settings != campaign.setting_count()) {
    throw_runtime_error("campaign journal " + shown_path(path) + ": its header counts " +
                        std::to_string(contents->settings) + " settings, the campaign " +
                        std::to_string(campaign.setting_count()));
  }
  if (contents->shard.index != shard.index || contents->shard.count != shard.count) {
    throw_usage_error(shown_path(dir) + " holds shard " + journal::shard_text(contents->shard) +
                      " of this campaign, not shard " + journal::shard_text(shard) +
                      "; use one directory per shard");
  }
  check_rows_are_their_settings(campaign, *contents, path);
  return *contents;
}

// Decodes image `i` of the campaign (a PNG or TIFF file of at most
// kMaxCampaignImageBytes, read as the simulator reads it: decode_image),
// checking that the file still has the digest the campaign was made with.
Image load_image(const ResolvedCampaign& campaign, int i) {
  const CampaignImage& image = campaign.images[i];
  const std::string data =
      campaign_input::read_image_file(image.path, kMaxCampaignImageBytes, "image");
  if (sha256_hex(data) != image.sha256) {
    throw_runtime_error("image " + shown_path(image.path) +
                        " changed since the campaign started (its SHA-256 differs)");
  }
  return decode_image(reinterpret_cast<const std::uint8_t*>(data.data()), data.size(), image.path);
}

// An exclusive lock on DIR/.campaign.lock for the life of the object: two
// runs into one directory would both append to its journal. The kernel
// releases it when the process dies, kill -9 included.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& dir) {
    const std::string path = (fs::path(dir) / kLockName).string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      throw_runtime_error("cannot create " + shown_path(path) + ": " + std::strerror(errno));
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      throw_usage_error(shown_path(dir) +
                        " is in use by another fssim campaign run; wait for it or use another "
                        "directory");
    }
  }
  ~DirectoryLock() { ::close(fd_); }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// The files a run or a merge writes into its directory.
std::vector<std::string> written_names() {
  return {kCampaignJournal,  kCampaignResultsCsv, kCampaignResultsJsonl,
          kCampaignManifest, kCampaignTrialsCsv,  kCampaignTrialsJsonl,
          kLockName};
}

// Refuses (a usage fss::Error) to run when a file the command writes into
// `dir` is one of `inputs` (the same file: device and inode). A file that
// does not exist yet is no input.
void refuse_outputs_over_inputs(const std::string& dir, const std::vector<std::string>& inputs) {
  for (const std::string& name : written_names()) {
    const std::string output = (fs::path(dir) / name).string();
    for (const std::string& input : inputs) {
      if (same_file(output, input)) {
        throw_usage_error("the output " + shown_path(output) + " would replace the input " +
                          shown_path(input) + "; use another output directory");
      }
    }
  }
}

// The files a campaign reads: its images, its code files, its velocity files, and `others`.
std::vector<std::string> campaign_inputs(const ResolvedCampaign& campaign,
                                         const std::vector<std::string>& others) {
  std::vector<std::string> inputs = others;
  for (const CampaignImage& image : campaign.images) inputs.push_back(image.path);
  for (const CampaignCode& code : campaign.codes) {
    if (!builtin_code(code.name)) inputs.push_back(code.name);
  }
  for (const CampaignDistribution& d : campaign.velocity_distributions) {
    if (d.distribution.kind == VelocityDistributionKind::kDiscrete) inputs.push_back(d.name);
  }
  return inputs;
}

// Creates dir and its missing parents; those created, outermost first.
std::vector<fs::path> create_campaign_directory(const std::string& dir, const char* what) {
  std::error_code ec;
  std::vector<fs::path> created = detail::create_directories_listed(dir, ec);
  if (ec || !fs::is_directory(dir, ec)) {
    detail::remove_created_directories(created);
    throw_runtime_error(std::string("cannot create ") + what + " " + shown_path(dir) +
                        (ec ? ": " + ec.message() : std::string()));
  }
  return created;
}

// After a failed run into a directory it created: the lock file, and the
// journal while it holds no setting, are removed (this run wrote both).
void remove_unstarted_journal(const std::string& dir) {
  const std::string path = (fs::path(dir) / kCampaignJournal).string();
  try {
    const std::optional<journal::Contents> contents = journal::read(path);
    if (contents && !contents->rows.empty()) return;
  } catch (const Error&) {
    return;
  }
  ::unlink(path.c_str());
  ::unlink((fs::path(dir) / kLockName).c_str());
}

// Images of at most this many samples run their settings side by side, one thread each: a small
// image's run has serial parts (decoding, planning, the RMSE_CI ranking) that leave cores idle,
// where a large image's keeps every thread busy on its own.
constexpr long long kSideBySideMaxSamples = 1LL << 22;

// How many settings of `block` (indices of settings of `image`) run at once: the threads, when the
// image is small and that many of its largest runs fit in the memory limit together; else 1.
int setting_lanes(const ResolvedCampaign& campaign, std::span<const long long> block,
                  const Image& image, const CampaignRunOptions& options) {
  const int threads = resolve_thread_count(options.threads);
  const long long samples = static_cast<long long>(image.width) * image.height * image.channels;
  if (threads < 2 || block.size() < 2 || samples > kSideBySideMaxSamples) return 1;
  const int lanes = static_cast<int>(std::min<std::size_t>(threads, block.size()));
  if (options.max_memory_bytes == 0) return lanes;
  const ImageShape shape{image.width, image.height, image.channels};
  std::size_t largest = kBaselineMemoryBytes;
  for (const long long i : block) {
    const Setting s = setting_at(campaign, i);
    SimulationOptions o = setting_options(campaign, s);
    o.threads = 1;
    try {
      largest = std::max(largest,
                         estimate_run_memory_bytes(shape, o, campaign.codes[s.code].code, false));
    } catch (const Error&) {  // a setting that cannot run uses no memory
    }
  }
  // The process's baseline counts once, each run's own part once per lane.
  const std::size_t each = largest - kBaselineMemoryBytes;
  for (int n = lanes; n > 1; --n) {
    if (kBaselineMemoryBytes + each * static_cast<std::size_t>(n) <= options.max_memory_bytes) {
      return n;
    }
  }
  return 1;
}

// What run_shard's settings share: the journal and its appender, the plans, the summary and the
// progress.
struct ShardState {
  journal::Contents contents;
  journal::Appender* appender = nullptr;
  SimulationPlanCache plans;  // each kernel once per code, mode, velocities, dt and width
  CampaignRunSummary summary;
  CampaignProgress progress;
  std::chrono::steady_clock::time_point start;
};

// Runs the settings `block` of `image` (setting_lanes of them at a time, each with one thread, or
// one at a time with options.threads) and journals each, in block order, once it and those before
// it have ended: the journal's bytes do not depend on the lanes.
void run_block(const ResolvedCampaign& campaign, std::span<const long long> block,
               const Image& image, const CampaignRunOptions& options, ShardState& state) {
  const int lanes = setting_lanes(campaign, block, image, options);
  const SettingRunOptions run_options{lanes > 1 ? 1 : options.threads, options.max_memory_bytes,
                                      options.fssim_version};
  const int count = static_cast<int>(block.size());
  std::vector<ResultRow> rows(block.size());
  std::vector<std::vector<ResultRow>> trial_rows(campaign.per_trial ? block.size() : 0);
  const auto trials_of = [&](int k) { return campaign.per_trial ? &trial_rows[k] : nullptr; };
  const auto work = [&](int k, int) {
    rows[k] = run_setting(campaign, setting_at(campaign, block[k]), image, run_options,
                          &state.plans, trials_of(k));
  };
  const auto commit = [&](int k) {
    const long long i = block[k];
    state.appender->append(journal::row_line(i, rows[k], trials_of(k)));
    if (campaign.per_trial) state.contents.trial_rows[i] = std::move(trial_rows[k]);
    state.contents.rows[i] = std::move(rows[k]);
    ++state.summary.ran;
    state.progress.done = static_cast<long long>(state.contents.rows.size());
    state.progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - state.start).count();
    if (options.progress) options.progress(state.progress);
  };
  ordered_parallel_for(count, lanes, work, commit);
}

// The settings of the shard missing from the journal, in product order.
std::vector<long long> pending_settings(const ResolvedCampaign& campaign,
                                        const journal::Contents& contents,
                                        const CampaignShard& shard) {
  std::vector<long long> pending;
  const long long settings = campaign.setting_count();
  for (long long i = shard.index - 1; i < settings; i += shard.count) {
    if (!contents.rows.count(i)) pending.push_back(i);
  }
  return pending;
}

// Runs the settings of the shard missing from dir's journal; dir is locked. DIR/journal.jsonl is
// append-only: a header line naming the campaign (its canonical specification and hash) and the
// shard, then one line per finished setting, in product order, written as soon as the setting
// and those before it end (so a killed process loses none of those) and fsynced, while the next
// settings run, before the next line is written. A rerun reads it and runs only the settings it
// lacks (a torn last line, from a kill mid-write, is cut off); a different campaign or shard is
// refused. Once every setting of the shard is in the journal, results.csv, results.jsonl and
// campaign.json (and, with per_trial, trials.csv and trials.jsonl) are written from it, each to a
// temporary file renamed into place. Settings are image-major: each image is decoded once.
CampaignRunSummary run_shard(const ResolvedCampaign& campaign, const std::string& dir,
                             const CampaignRunOptions& options) {
  ShardState state;
  state.contents = open_journal(campaign, dir, options.shard);
  state.start = std::chrono::steady_clock::now();
  state.summary.total = journal::shard_size(campaign.setting_count(), options.shard);
  state.summary.resumed = static_cast<long long>(state.contents.rows.size());
  state.progress = {state.summary.resumed, state.summary.total, state.summary.resumed, 0.0};
  if (options.progress) options.progress(state.progress);
  journal::Appender appender((fs::path(dir) / kCampaignJournal).string(),
                             state.contents.valid_bytes);
  state.appender = &appender;
  const std::vector<long long> pending = pending_settings(campaign, state.contents, options.shard);
  for (std::size_t first = 0; first < pending.size();) {
    const int image_index = setting_at(campaign, pending[first]).image;
    std::size_t end = first + 1;
    while (end < pending.size() && setting_at(campaign, pending[end]).image == image_index) ++end;
    const Image image = load_image(campaign, image_index);
    run_block(campaign, std::span<const long long>(pending).subspan(first, end - first), image,
              options, state);
    first = end;
  }
  appender.finish();
  state.summary.plans_built = state.plans.built();
  state.summary.plans_reused = state.plans.reused();
  write_results(dir, campaign, options.shard, state.contents, &state.summary.rows);
  return state.summary;
}

}  // namespace

CampaignRunSummary RunCampaign(const ResolvedCampaign& campaign, const std::string& dir,
                               const CampaignRunOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  refuse_outputs_over_inputs(dir, campaign_inputs(campaign, options.inputs));
  const std::vector<fs::path> created = create_campaign_directory(dir, "the campaign directory");
  try {
    const DirectoryLock lock(dir);
    try {
      return run_shard(campaign, dir, options);
    } catch (...) {
      if (!created.empty()) remove_unstarted_journal(dir);
      throw;
    }
  } catch (...) {
    // A failed run leaves no directory it created but one holding results.
    detail::remove_created_directories(created);
    throw;
  }
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
    throw_usage_error("part " + shown_path(dir) + " is not a campaign directory (no " +
                      kCampaignJournal + ")");
  }
  return {dir, std::move(*contents)};
}

void check_parts(const std::vector<Part>& parts) {
  const journal::Contents& first = parts.front().contents;
  std::set<int> seen;
  for (const Part& part : parts) {
    const journal::Contents& c = part.contents;
    const std::string name = "part " + shown_path(part.dir);
    if (c.campaign_sha256 != first.campaign_sha256) {
      throw_usage_error(name + " belongs to campaign " + short_hash(c.campaign_sha256) + ", " +
                        shown_path(parts.front().dir) + " to campaign " +
                        short_hash(first.campaign_sha256) + ": they cannot be merged");
    }
    if (c.shard.count != first.shard.count) {
      throw_usage_error(name + " is shard " + journal::shard_text(c.shard) + ", but " +
                        shown_path(parts.front().dir) + " is shard " +
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

// The parts of a merge into dir, read and checked to make one campaign,
// which *campaign receives.
std::vector<Part> read_parts(const std::vector<std::string>& part_dirs, const std::string& dir,
                             ResolvedCampaign* campaign) {
  if (part_dirs.empty()) throw_usage_error("campaign merge needs at least one part");
  std::vector<std::string> journals;
  journals.reserve(part_dirs.size());
  for (const std::string& part : part_dirs) {
    if (same_file(part, dir)) {
      throw_usage_error("the merge output " + shown_path(dir) + " must not be one of the parts");
    }
    journals.push_back((fs::path(part) / kCampaignJournal).string());
  }
  refuse_outputs_over_inputs(dir, journals);
  std::vector<Part> parts;
  parts.reserve(part_dirs.size());
  for (const std::string& part : part_dirs) parts.push_back(read_part(part));
  check_parts(parts);
  try {
    *campaign = campaign_from_canonical_json(parts.front().contents.campaign_json);
  } catch (const Error& e) {
    throw_runtime_error("campaign journal " + shown_path(journals.front()) + ": " + e.what());
  }
  if (campaign->sha256 != parts.front().contents.campaign_sha256) {
    throw_runtime_error("part " + shown_path(parts.front().dir) +
                        ": its journal's specification does not match its hash");
  }
  for (const Part& part : parts) {
    if (part.contents.settings != campaign->setting_count()) {
      throw_runtime_error("part " + shown_path(part.dir) + ": its journal's header counts " +
                          std::to_string(part.contents.settings) + " settings, the campaign " +
                          std::to_string(campaign->setting_count()));
    }
    check_rows_are_their_settings(*campaign, part.contents,
                                  (fs::path(part.dir) / kCampaignJournal).string());
  }
  return parts;
}

// Writes the merged journal and results into dir, which exists.
std::vector<ResultRow> write_merged(std::vector<Part>& parts, const ResolvedCampaign& campaign,
                                    const std::string& dir) {
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
  if (const auto existing = journal::read((fs::path(dir) / kCampaignJournal).string())) {
    if (existing->campaign_sha256 != campaign.sha256) {
      throw_usage_error(shown_path(dir) + " holds another campaign (" +
                        short_hash(existing->campaign_sha256) + "); use a new output directory");
    }
  }
  write_file_durably((fs::path(dir) / kCampaignJournal).string(), journal_text);
  std::vector<ResultRow> ordered;
  write_results(dir, campaign, {1, 1}, merged, &ordered);
  return ordered;
}

}  // namespace

std::vector<ResultRow> MergeCampaignParts(const std::vector<std::string>& part_dirs,
                                          const std::string& dir, ResolvedCampaign* out) {
  ResolvedCampaign campaign;
  std::vector<Part> parts = read_parts(part_dirs, dir, &campaign);
  const std::vector<fs::path> created = create_campaign_directory(dir, "the merge output");
  std::vector<ResultRow> ordered;
  try {
    ordered = write_merged(parts, campaign, dir);
  } catch (...) {
    // In a directory this merge created, every file is its own.
    if (!created.empty()) {
      for (const std::string& name : written_names()) ::unlink((fs::path(dir) / name).c_str());
    }
    detail::remove_created_directories(created);
    throw;
  }
  if (out) *out = campaign;
  return ordered;
}

}  // namespace fss
