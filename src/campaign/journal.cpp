#include "campaign/journal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "campaign/user_input.h"
#include "fss/core/error.h"

namespace fss::campaign_journal {

namespace {

using Json = nlohmann::json;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw_runtime_error("campaign journal '" + escape_control_characters(path) + "': " + what);
}

// j[key] as an integer; throws std::invalid_argument if it is none.
long long integer_at(const Json& j, const char* key) {
  const std::optional<long long> n = campaign_input::json_integer(j.at(key));
  if (!n) throw std::invalid_argument(std::string("'") + key + "' is not an integer");
  return *n;
}

std::string line_text(int number) { return "line " + std::to_string(number); }

Json parse_line(const std::string& path, std::string_view line, int number) {
  std::string error;
  std::optional<Json> j = campaign_input::parse_json(line, &error);
  if (!j) fail(path, "malformed " + line_text(number) + ": " + error);
  if (!j->is_object()) fail(path, "malformed " + line_text(number) + ": expected an object");
  return std::move(*j);
}

void parse_header(const std::string& path, std::string_view line, Contents& c) {
  const Json j = parse_line(path, line, 1);
  try {
    if (integer_at(j, "fssim_campaign_journal") != 1) fail(path, "unknown journal version");
    c.campaign_json = j.at("campaign").get<std::string>();
    c.campaign_sha256 = j.at("campaign_sha256").get<std::string>();
    c.settings = integer_at(j, "settings");
    const std::string shard = j.at("shard").get<std::string>();
    try {
      c.shard = parse_shard(shard);
    } catch (const Error&) {
      fail(path, "malformed header line: shard '" + shorten_for_message(shard) + "'");
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, "malformed header line: " + shorten_for_message(e.what(), 200));
  }
  if (c.settings < 1 || c.settings > kMaxCampaignSettings) {
    fail(path, "malformed header line: " + std::to_string(c.settings) + " settings");
  }
}

// Whether `text` is a number as JSON writes it (and shortest() does):
// -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?, whose value is finite.
bool is_json_number(const std::string& text) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    return i - start;
  };
  if (i < text.size() && text[i] == '-') ++i;
  const std::size_t start = i;
  const std::size_t integer = digits();
  if (integer == 0 || (integer > 1 && text[start] == '0')) return false;
  if (i < text.size() && text[i] == '.') {
    ++i;
    if (digits() == 0) return false;
  }
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return i == text.size() && ec == std::errc() && end == text.data() + text.size();
}

// Whether `cell` is a value of a column of `kind` as a row holds it: a
// number (or empty, inf, -inf, nan), true or false.
bool fits(const std::string& cell, ColumnKind kind) {
  if (kind == ColumnKind::kText || cell.empty()) return true;
  if (kind == ColumnKind::kBoolean) return cell == "true" || cell == "false";
  return cell == "inf" || cell == "-inf" || cell == "nan" || is_json_number(cell);
}

bool row_fits(const ResultRow& row, const std::vector<ResultColumn>& columns) {
  if (row.size() != columns.size()) return false;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (!fits(row[i], columns[i].kind)) return false;
  }
  return true;
}

void parse_row(const std::string& path, std::string_view line, int number, Contents& c) {
  const Json j = parse_line(path, line, number);
  const std::string where = line_text(number);
  long long index = -1;
  try {
    index = integer_at(j, "index");
    ResultRow row = j.at("row").get<ResultRow>();
    // A row an earlier fssim journalled (results schema 2) resumes in the present columns.
    if (auto present = upgrade_schema2_row(row, false)) row = std::move(*present);
    // A row of schema 3, or of schema 4 (a campaign with velocity distributions); which one the
    // campaign has is checked against it (row_setting_mismatch).
    const bool fits_row =
        row_fits(row, campaign_columns()) || row_fits(row, campaign_columns(true));
    if (index < 0 || index >= c.settings || !fits_row) {
      fail(path, where + " does not fit the campaign");
    }
    if (index % c.shard.count != c.shard.index - 1) {
      fail(path, where + " holds setting " + std::to_string(index) + ", which belongs to shard " +
                     shard_text({static_cast<int>(index % c.shard.count) + 1, c.shard.count}) +
                     ", not to this journal's shard " + shard_text(c.shard));
    }
    if (const auto trials = j.find("trials"); trials != j.end()) {
      std::vector<ResultRow> rows = trials->get<std::vector<ResultRow>>();
      for (ResultRow& trial : rows) {
        if (auto present = upgrade_schema2_row(trial, true)) trial = std::move(*present);
        if (!row_fits(trial, trial_columns()) && !row_fits(trial, trial_columns(true))) {
          fail(path, where + " has a trial row that does not fit");
        }
      }
      c.trial_rows[index] = std::move(rows);
    }
    c.rows[index] = std::move(row);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, "malformed " + where + ": " + shorten_for_message(e.what(), 200));
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
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return std::nullopt;
    fail(path, std::string("cannot be read: ") + std::strerror(errno));
  }
  if (::stat(path.c_str(), &st) != 0) {
    fail(path, std::string("cannot be read: ") + std::strerror(errno));
  }
  if (!S_ISREG(st.st_mode)) {
    fail(path,
         "not an fssim campaign journal (not a regular file); move it away or use another "
         "directory");
  }
  return parse(campaign_input::read_text_file(path, kMaxCampaignJournalBytes, "campaign journal"),
               path);
}

Contents parse(std::string_view bytes, const std::string& path) {
  Contents c;
  c.file_bytes = bytes.size();
  const std::size_t header_end = bytes.find('\n');
  if (header_end == std::string_view::npos) {
    // fssim writes the header whole (renamed into place): this is not its.
    fail(path,
         "not an fssim campaign journal (no complete header line); move it away or use "
         "another directory");
  }
  parse_header(path, bytes.substr(0, header_end), c);
  std::size_t begin = header_end + 1;
  int number = 2;
  while (begin < bytes.size()) {
    const std::size_t end = bytes.find('\n', begin);
    if (end == std::string_view::npos) break;  // a torn last line: cut off on append
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
