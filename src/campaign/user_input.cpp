#include "campaign/user_input.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>

#include "fss/core/error.h"

namespace fss::campaign_input {

namespace {

using Json = nlohmann::json;

// Closes a descriptor on destruction.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// Thrown by the parser callback to stop at the first level too deep.
struct TooDeep {};

// The signatures of the image files the simulator reads (image_io.h): PNG,
// and TIFF or BigTIFF in either byte order (tiff_io.h).
constexpr std::string_view kImageSignatures[] = {
    std::string_view("\x89PNG\r\n\x1a\n", 8), std::string_view("II*\0", 4),
    std::string_view("MM\0*", 4), std::string_view("II+\0", 4), std::string_view("MM\0+", 4)};

// Refuses what the first bytes of a file already tell: none of the
// signatures (decided once as many bytes as the longest came, or the end), a
// NUL byte in a text. `checked` bytes of `bytes` passed before.
void check_kind(const std::string& named, const std::string& bytes, const FileKind& kind,
                bool at_end, std::size_t checked) {
  std::size_t longest = 0;
  for (const std::string_view s : kind.signatures) longest = std::max(longest, s.size());
  if (checked < longest && (at_end || bytes.size() >= longest) &&
      std::none_of(kind.signatures.begin(), kind.signatures.end(),
                   [&](std::string_view s) { return std::string_view(bytes).starts_with(s); })) {
    throw_runtime_error(named + " is not " + kind.expected);
  }
  if (kind.text && bytes.find('\0', checked) != std::string::npos) {
    throw_runtime_error(named + " is not " + kind.expected + " (it holds a NUL byte)");
  }
}

}  // namespace

std::string read_file(const std::string& path, const std::string& what, const FileKind& kind) {
  const std::string named = what + " '" + escape_control_characters(path) + "'";
  const auto too_large = [&] {
    throw_runtime_error(named + " is larger than " +
                        format_bytes(static_cast<double>(kind.max_bytes)) + ", the most a " + what +
                        " may have");
  };
  FileDescriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  if (file.fd < 0) throw_runtime_error("cannot open " + named + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) {
    throw_runtime_error("cannot read " + named + ": " + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) throw_runtime_error(named + " is a directory, expected a file");
  const bool regular = S_ISREG(st.st_mode);
  if (regular && static_cast<std::uintmax_t>(st.st_size) > kind.max_bytes) too_large();
  std::string bytes;
  if (regular) bytes.reserve(static_cast<std::size_t>(st.st_size));
  char buffer[1 << 16];
  for (;;) {
    // At most max_bytes + 1 in all: one byte past the limit tells it is passed.
    const std::size_t room = std::min(sizeof buffer, kind.max_bytes + 1 - bytes.size());
    const ssize_t got = ::read(file.fd, buffer, room);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw_runtime_error("cannot read " + named + ": " + std::strerror(errno));
    const std::size_t checked = bytes.size();
    bytes.append(buffer, static_cast<std::size_t>(got));
    check_kind(named, bytes, kind, got == 0, checked);
    if (bytes.size() > kind.max_bytes) too_large();
    if (got == 0) return bytes;
  }
}

std::string read_text_file(const std::string& path, std::size_t max_bytes,
                           const std::string& what) {
  return read_file(path, what, {max_bytes, {}, "a text file", true});
}

std::string read_image_file(const std::string& path, std::size_t max_bytes,
                            const std::string& what) {
  return read_file(path, what, {max_bytes, kImageSignatures, "a PNG or TIFF file"});
}

std::optional<Json> parse_json(std::string_view text, std::string* error) {
  // The callback sees each array or object as it starts, at the depth of its
  // parent (0 for the outermost): depth d opens level d + 1.
  const Json::parser_callback_t bound = [](int depth, Json::parse_event_t event, Json&) {
    const bool opens =
        event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start;
    if (opens && depth >= kMaxJsonDepth) throw TooDeep{};
    return true;
  };
  try {
    return Json::parse(text, bound);
  } catch (const TooDeep&) {
    *error = "arrays and objects nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";
  } catch (const Json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, ...": the
    // library's tag is not the user's business.
    std::string_view what = e.what();
    if (const std::size_t tag = what.find("] "); what.starts_with("[json.") && tag != what.npos) {
      what.remove_prefix(tag + 2);
    }
    *error = shorten_for_message(std::string(what), 200);
  }
  return std::nullopt;
}

std::optional<long long> json_integer(const Json& value) {
  if (value.is_number_unsigned()) {
    const auto n = value.get<std::uint64_t>();
    if (n > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) return std::nullopt;
    return static_cast<long long>(n);
  }
  if (value.is_number_integer()) return value.get<long long>();
  return std::nullopt;
}

std::optional<std::uint64_t> json_unsigned(const Json& value) {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  return std::nullopt;
}

std::string describe_json(const Json& value) {
  if (value.is_array()) return "an array of " + std::to_string(value.size());
  if (value.is_object()) return "an object of " + std::to_string(value.size()) + " keys";
  if (value.is_string()) {
    std::string text = "'";
    text += shorten_for_message(value.get_ref<const std::string&>());
    return text + "'";
  }
  if (value.is_binary()) return "binary data";
  return value.dump();  // a number, true, false or null: a few bytes
}

}  // namespace fss::campaign_input
