#include "fss/code.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "fss/error.h"

namespace fss {

std::string to_string(ShutterMode mode) {
  return mode == ShutterMode::kAnalog ? "analog" : "numerical";
}

std::optional<ShutterMode> shutter_mode_from_string(std::string_view text) {
  if (text == "numerical") return ShutterMode::kNumerical;
  if (text == "analog") return ShutterMode::kAnalog;
  return std::nullopt;
}

namespace {
bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' || c == ',' ||
         c == ';';
}
}  // namespace

ShutterCode parse_code_text(std::string_view text, const std::string& origin) {
  ShutterCode code;
  code.name = origin;
  int line = 1;
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
      const std::string_view token = text.substr(i, end - i);
      // from_chars does not take a leading '+'; accept it as people write it.
      std::string_view digits = token;
      if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
      double value = 0.0;
      const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
      const std::string where = "code file '" + origin + "' line " + std::to_string(line);
      if (ec != std::errc() || ptr != digits.data() + digits.size()) {
        throw_runtime_error(where + ": '" + std::string(token) +
                            "' is not a number (expected gains separated by spaces, commas or "
                            "semicolons)");
      }
      if (!std::isfinite(value)) {
        throw_runtime_error(where + ": gain '" + std::string(token) + "' is not a finite number");
      }
      code.gains.push_back(value);
      i = end;
    }
  }
  if (code.gains.empty()) {
    throw_runtime_error("code file '" + origin + "' holds no gains (expected at least one number)");
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

ShutterCode load_code(const std::string& name_or_path) {
  if (auto code = builtin_code(name_or_path)) return *code;
  std::error_code ec;
  const std::filesystem::path path(name_or_path);
  if (!std::filesystem::exists(path, ec)) {
    std::string names;
    for (const auto& n : builtin_code_names()) names += (names.empty() ? "" : ", ") + n;
    throw_usage_error("--code '" + name_or_path + "' is neither a built-in code (" + names +
                      ") nor an existing file");
  }
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error("code file '" + name_or_path + "' is a directory, expected a text file");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw_runtime_error("cannot open code file '" + name_or_path + "': " + std::strerror(errno));
  }
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) throw_runtime_error("cannot read code file '" + name_or_path + "'");
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
