#include "fss/error.h"

#include <cstdio>

namespace fss {

Error::Error(ErrorKind kind, const std::string& message)
    : std::runtime_error(message), kind_(kind) {}

void throw_usage_error(const std::string& message) { throw Error(ErrorKind::kUsage, message); }

void throw_runtime_error(const std::string& message) { throw Error(ErrorKind::kRuntime, message); }

void throw_limit_error(const std::string& message) { throw Error(ErrorKind::kLimit, message); }

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
  return buffer;
}

}  // namespace fss
