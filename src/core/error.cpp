#include "fss/core/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace fss {

Error::Error(ErrorKind kind, const std::string& message)
    : std::runtime_error(message), kind_(kind) {}

void throw_usage_error(const std::string& message) { throw Error(ErrorKind::kUsage, message); }

void throw_runtime_error(const std::string& message) { throw Error(ErrorKind::kRuntime, message); }

void throw_limit_error(const std::string& message) { throw Error(ErrorKind::kLimit, message); }

namespace {

// `bytes` in the largest binary unit it reaches, with `decimals` decimals
// (none in bytes), rounded up when `up`: a size stated as needed is never
// below the true one, so a limit raised to it is enough.
std::string format_size(double bytes, int decimals, bool up) {
  static const char* const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  if (unit == 0) decimals = 0;
  if (up) {
    const double scale = std::pow(10.0, decimals);
    bytes = std::ceil(bytes * scale) / scale;
  }
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f %s", decimals, bytes, units[unit]);
  return buffer;
}

}  // namespace

std::string format_bytes(double bytes) { return format_size(bytes, 1, false); }

void throw_memory_limit_error(const std::string& subject, std::size_t needed, std::size_t limit) {
  const auto sizes = format_bytes_distinct(static_cast<double>(needed), static_cast<double>(limit));
  throw_limit_error(subject + " needs about " + sizes.first +
                    " of memory, more than the memory limit of " + sizes.second);
}

std::pair<std::string, std::string> format_bytes_distinct(double needed, double limit) {
  // More decimals until the two differ: whole bytes need at most 13 below 1024^4.
  std::pair<std::string, std::string> texts;
  for (int decimals = 1; decimals <= 13; ++decimals) {
    texts = {format_size(needed, decimals, true), format_size(limit, decimals, false)};
    if (texts.first != texts.second || needed == limit) break;
  }
  return texts;
}

// The one formatter of values in messages: %g would write 1.0000001 as "1" and hide that it is
// above 1.
std::string format_exact(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // The shortest digits that read back (std::to_chars), laid out as %g lays
  // out P = max(digits, 6) of them: exponent form for X < -4 or X >= P.
  char text[64];
  const auto sci = std::to_chars(text, text + sizeof text, value, std::chars_format::scientific);
  const std::string_view scientific(text, static_cast<std::size_t>(sci.ptr - text));
  const std::size_t e = scientific.find('e');
  int exponent = 0;
  std::from_chars(scientific.data() + e + (scientific[e + 1] == '+' ? 2 : 1), sci.ptr, exponent);
  const auto digits = static_cast<int>(
      std::count_if(scientific.begin(), scientific.begin() + static_cast<std::ptrdiff_t>(e),
                    [](char c) { return c >= '0' && c <= '9'; }));
  if (exponent < -4 || exponent >= std::max(digits, 6)) return std::string(scientific);
  const auto fixed = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return std::string(text, fixed.ptr);
}

std::string format_number(double value, int significant_digits) {
  if (std::isnan(value)) return "nan";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant_digits, value);
  return buffer;
}

// So that a binary file or a long argument still gives a short, one-line message.
std::string shorten_for_message(std::string_view text, std::size_t shown) {
  std::string out;
  std::size_t used = 0;
  for (; used < text.size() && out.size() < shown; ++used) {
    out += escape_control_characters(text.substr(used, 1));
  }
  if (used < text.size()) out += "...";
  return out;
}

std::string escape_control_characters(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 0xf];
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace fss
