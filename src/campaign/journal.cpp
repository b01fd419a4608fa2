#include "campaign/journal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fss/core/error.h"

namespace fss::campaign_journal {

namespace {

using Json = nlohmann::json;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw_runtime_error("campaign journal '" + escape_control_characters(path) + "': " + what);
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) fail(path, "cannot be read");
  return bytes.str();
}

void parse_header(const std::string& path, const std::string& line, Contents& c) {
  try {
    const Json j = Json::parse(line);
    if (j.at("fssim_campaign_journal").get<int>() != 1) fail(path, "unknown journal version");
    c.campaign_json = j.at("campaign").get<std::string>();
    c.campaign_sha256 = j.at("campaign_sha256").get<std::string>();
    c.shard = parse_shard(j.at("shard").get<std::string>());
    c.settings = j.at("settings").get<long long>();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, std::string("malformed header line: ") + e.what());
  }
}

void parse_row(const std::string& path, const std::string& line, int number, Contents& c) {
  try {
    const Json j = Json::parse(line);
    const long long index = j.at("index").get<long long>();
    ResultRow row = j.at("row").get<ResultRow>();
    if (index < 0 || index >= c.settings || row.size() != campaign_columns().size()) {
      fail(path, "line " + std::to_string(number) + " does not fit the campaign");
    }
    if (const auto trials = j.find("trials"); trials != j.end()) {
      std::vector<ResultRow> rows = trials->get<std::vector<ResultRow>>();
      for (const ResultRow& trial : rows) {
        if (trial.size() != trial_columns().size()) {
          fail(path, "line " + std::to_string(number) + " has a trial row that does not fit");
        }
      }
      c.trial_rows[index] = std::move(rows);
    }
    c.rows[index] = std::move(row);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, "malformed line " + std::to_string(number) + ": " + e.what());
  }
}

}  // namespace

std::string shard_text(const CampaignShard& shard) {
  return std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

long long shard_size(long long settings, const CampaignShard& shard) {
  const long long first = shard.index - 1;
  return first >= settings ? 0 : (settings - first - 1) / shard.count + 1;
}

std::optional<Contents> read(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  const std::string bytes = read_all(path);
  Contents c;
  c.file_bytes = bytes.size();
  const std::size_t header_end = bytes.find('\n');
  if (header_end == std::string::npos) {
    // Killed while the header was being written: nothing ran yet.
    std::filesystem::remove(path, ec);
    return std::nullopt;
  }
  parse_header(path, bytes.substr(0, header_end), c);
  std::size_t begin = header_end + 1;
  int number = 2;
  while (begin < bytes.size()) {
    const std::size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) break;  // a torn last line: cut off on append
    parse_row(path, bytes.substr(begin, end - begin), number++, c);
    begin = end + 1;
  }
  c.valid_bytes = begin;
  return c;
}

std::string header_line(const ResolvedCampaign& campaign, const CampaignShard& shard) {
  const Json j = {{"fssim_campaign_journal", 1},
                  {"campaign_sha256", campaign.sha256},
                  {"shard", shard_text(shard)},
                  {"settings", campaign.setting_count()},
                  {"campaign", campaign.canonical_json}};
  return j.dump() + "\n";
}

std::string row_line(long long index, const ResultRow& row,
                     const std::vector<ResultRow>* trial_rows) {
  Json j = {{"index", index}, {"row", row}};
  if (trial_rows != nullptr) j["trials"] = *trial_rows;
  return j.dump() + "\n";
}

Appender::Appender(const std::string& path, std::size_t valid_bytes) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) fail(path, std::string("cannot be opened: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) == 0 && static_cast<std::size_t>(st.st_size) > valid_bytes) {
    if (::ftruncate(fd_, static_cast<off_t>(valid_bytes)) != 0 || ::fsync(fd_) != 0) {
      fail(path, std::string("cannot cut its torn last line: ") + std::strerror(errno));
    }
  }
}

Appender::~Appender() {
  if (sync_.valid()) sync_.wait();
  if (fd_ >= 0) ::close(fd_);
}

void Appender::finish() {
  if (!sync_.valid()) return;
  if (const int error = sync_.get(); error != 0) {
    fail(path_, std::string("cannot be synced: ") + std::strerror(error));
  }
}

void Appender::append(const std::string& line) {
  finish();
  std::size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + written, line.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(path_, std::string("cannot be written: ") + std::strerror(errno));
    written += static_cast<std::size_t>(n);
  }
  const int fd = fd_;
  sync_ = std::async(std::launch::async, [fd] { return ::fdatasync(fd) == 0 ? 0 : errno; });
}

}  // namespace fss::campaign_journal
