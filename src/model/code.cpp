#include "fss/model/code.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/text_file.h"
#include "fss/core/error.h"

namespace fss {

namespace {
constexpr detail::EnumNames<ShutterMode, 2> kShutterModeNames{
    {{ShutterMode::kNumerical, "numerical"}, {ShutterMode::kAnalog, "analog"}}};
}  // namespace

std::string to_string(ShutterMode mode) { return detail::enum_name(kShutterModeNames, mode); }

std::optional<ShutterMode> shutter_mode_from_string(std::string_view text) {
  return detail::enum_from_name(kShutterModeNames, text);
}

namespace {
bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' || c == ',' ||
         c == ';';
}

// A token as shown in a message: control bytes as \xNN, cut after 40
// characters, so that a binary file gives a short, one-line message.
std::string printable_token(std::string_view token) { return shorten_for_message(token, 40); }

// One gain of a code file; `where` names the file and line for messages.
double parse_gain(std::string_view token, const std::string& where) {
  // from_chars does not take a leading '+'; accept it as people write it.
  std::string_view digits = token;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const bool whole = ptr == digits.data() + digits.size();
  // (Appended rather than "'" + ...: GCC 12 warns wrongly on that form.)
  std::string shown = "'";
  shown += printable_token(token);
  shown += "'";
  if (ec == std::errc::result_out_of_range && whole) {
    throw_runtime_error(where + ": gain " + shown +
                        " is out of the range of double-precision numbers");
  }
  if (ec != std::errc() || !whole) {
    throw_runtime_error(where + ": " + shown +
                        " is not a number (expected gains separated by spaces, commas or "
                        "semicolons)");
  }
  if (!std::isfinite(value)) {
    throw_runtime_error(where + ": gain " + shown + " is not a finite number");
  }
  return value;
}
}  // namespace

ShutterCode parse_code_text(std::string_view text, const std::string& origin) {
  ShutterCode code;
  code.name = origin;
  const std::string shown_origin = escape_control_characters(origin);
  std::size_t line = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (is_separator(c)) {
      ++i;
    } else {
      std::size_t end = i;
      while (end < text.size() && !is_separator(text[end]) && text[end] != '#') ++end;
      // kMaxCodeLength bounds the analysis of a code, which costs O(L^2): its |K| is scanned on
      // 64 L points of [0, pi], each a sum over the L gains.
      if (code.gains.size() == static_cast<std::size_t>(kMaxCodeLength)) {
        throw_runtime_error("code file '" + shown_origin + "' line " + std::to_string(line) +
                            ": more than " + std::to_string(kMaxCodeLength) +
                            " gains (the longest code fssim analyses)");
      }
      code.gains.push_back(
          parse_gain(text.substr(i, end - i),
                     "code file '" + shown_origin + "' line " + std::to_string(line)));
      i = end;
    }
  }
  if (code.gains.empty()) {
    throw_runtime_error("code file '" + shown_origin +
                        "' holds no gains (expected at least one number)");
  }
  return code;
}

std::vector<std::string> builtin_code_names() {
  std::vector<std::string> names;
  for (const auto& entry : detail::embedded_codes()) names.emplace_back(entry.name);
  return names;
}

std::optional<ShutterCode> builtin_code(std::string_view name) {
  for (const auto& entry : detail::embedded_codes()) {
    if (name == entry.name) {
      ShutterCode code = parse_code_text(entry.text, entry.name);
      code.name = entry.name;
      return code;
    }
  }
  return std::nullopt;
}

ShutterCode load_code(const std::string& name_or_path, const std::string& named_as) {
  if (auto code = builtin_code(name_or_path)) return *code;
  // Every message quotes the name with its control bytes as \xNN (a NUL would
  // end the message there).
  const std::string shown = escape_control_characters(name_or_path);
  if (name_or_path.find('\0') != std::string::npos) {
    // The file system would read the path only up to the NUL: another file.
    throw_usage_error(named_as + " '" + shown +
                      "' holds a NUL byte: no built-in code or file name has one");
  }
  std::error_code ec;
  const std::filesystem::path path(name_or_path);
  const bool exists = std::filesystem::exists(path, ec);
  if (ec) throw_runtime_error("cannot access code file '" + shown + "': " + ec.message());
  if (!exists) {
    std::string names;
    for (const auto& n : builtin_code_names()) names += (names.empty() ? "" : ", ") + n;
    throw_usage_error(named_as + " '" + shown + "' is neither a built-in code (" + names +
                      ") nor an existing file");
  }
  const std::string text = detail::read_bounded_text_file(path, kMaxCodeFileBytes, "code file",
                                                          shown, "a text file of gains");
  return parse_code_text(text, name_or_path);
}

std::string format_code_txt(const ShutterCode& code) {
  std::string out;
  for (const double g : code.gains) {
    char buffer[64];
    // Shortest text that reads back to the same double.
    const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, g);
    out.append(buffer, ptr);
    out += ";\n";
  }
  return out;
}

double gain_sum(const std::vector<double>& gains) {
  double s = 0.0;
  for (const double g : gains) s += g;
  return s;
}

double gain_square_sum(const std::vector<double>& gains) {
  double s = 0.0;
  for (const double g : gains) s += g * g;
  return s;
}

double gain_max_abs(const std::vector<double>& gains) {
  double m = 0.0;
  for (const double g : gains) m = std::max(m, std::abs(g));
  return m;
}

double normalized_l1(const std::vector<double>& gains) {
  const double sup = gain_max_abs(gains);
  if (sup == 0.0) return 0.0;
  double l1 = 0.0;
  for (const double g : gains) l1 += std::abs(g);
  return l1 / sup;
}

}  // namespace fss
