// Checks shared by the fuzz targets: how an expected fss::Error must look.
#pragma once

#include <cstddef>
#include <string_view>

#include "fss/core/error.h"

namespace fss::fuzz {

// A usage or runtime error with one short line of text: not empty, at most
// `max_bytes`, no control byte (no line break, no terminal escape).
inline void check_message(const Error& error, std::size_t max_bytes) {
  if (error.kind() == ErrorKind::kLimit) __builtin_trap();
  const std::string_view message = error.what();
  if (message.empty() || message.size() > max_bytes) __builtin_trap();
  for (const char c : message) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) __builtin_trap();
  }
}

}  // namespace fss::fuzz
