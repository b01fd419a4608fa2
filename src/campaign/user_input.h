// Reading the user's files in the campaign code: every file bounded in size
// before it is read, every JSON text bounded in nesting while it is parsed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace fss::campaign_input {

// Deepest nesting of arrays and objects a JSON text of the user may have
// (a campaign file or a journal line needs 4).
inline constexpr int kMaxJsonDepth = 64;

// What a file read must be: at most `max_bytes` long, and its kind.
struct FileKind {
  std::size_t max_bytes = 0;
  // The file starts with one of them, when not empty.
  std::span<const std::string_view> signatures;
  const char* expected = "";  // what it is, for a refusal: "a PNG or TIFF file"
  bool text = false;          // no NUL byte (a CSV or JSON text)
};

// The bytes of `path`, `what` ("campaign file") naming it in messages.
// Refused with a runtime fss::Error "<what> '<path>' is larger than <max>,
// the most a <what> may have" when longer than kind.max_bytes: a regular
// file by its size before anything is read, any other kind (a FIFO,
// /dev/zero) once max_bytes + 1 bytes came; also, as soon as the bytes read
// tell, a file that starts with none of kind.signatures ("is not <expected>")
// and a text file holding a NUL byte. A directory, and a file that cannot be
// opened or read, are refused naming `what` and `path`.
std::string read_file(const std::string& path, const std::string& what, const FileKind& kind);

// A text file (CSV, JSON) of at most `max_bytes`, as read_file.
std::string read_text_file(const std::string& path, std::size_t max_bytes, const std::string& what);

// An image file the simulator reads, PNG or TIFF (its signature checked
// first), of at most `max_bytes`, as read_file.
std::string read_image_file(const std::string& path, std::size_t max_bytes,
                            const std::string& what);

// `text` parsed as JSON, or nullopt with *error set to a one-line reason (a
// syntax error as the parser tells it, shortened, or nesting deeper than
// kMaxJsonDepth, refused while parsing).
std::optional<nlohmann::json> parse_json(std::string_view text, std::string* error);

// `value` as an integer when it is an integer JSON number that long long
// holds (get<long long>() of a float out of range is undefined), else
// nullopt; likewise as an unsigned 64-bit integer.
std::optional<long long> json_integer(const nlohmann::json& value);
std::optional<std::uint64_t> json_unsigned(const nlohmann::json& value);

// `value` for a message: a number, boolean or null as JSON, a string quoted
// and shortened, an array or object by its kind only ("an array of 3").
std::string describe_json(const nlohmann::json& value);

}  // namespace fss::campaign_input
