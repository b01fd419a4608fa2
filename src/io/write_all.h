// Private helper of the writers in src/io/: a whole buffer to a descriptor.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <string_view>

namespace fss::detail {

// Writes all of `bytes` to `fd`, again after a signal or a short write;
// returns 0, or the errno of the failure (EIO when write() wrote nothing).
inline int write_all(int fd, std::string_view bytes) {
  const char* data = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return written < 0 ? errno : EIO;
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  return 0;
}

}  // namespace fss::detail
