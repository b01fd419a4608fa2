#include "core/stderr_capture.h"

#include "fss/core/error.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

namespace fss::detail {

// Held by a capture from start to end, and by write_stderr.
std::mutex g_capture_mutex;

}  // namespace fss::detail

namespace fss {

// Takes the capture's mutex: the plots capture descriptor 2 while they draw (to keep PLplot's
// messages off it), and a message written meanwhile from another thread would be captured with
// them.
void write_stderr(std::string_view text) {
  const std::lock_guard<std::mutex> lock(detail::g_capture_mutex);
  std::fwrite(text.data(), 1, text.size(), stderr);
  std::fflush(stderr);
}

}  // namespace fss

namespace fss::detail {

StderrCapture::StderrCapture() : lock_(g_capture_mutex) {
  std::fflush(stderr);
  captured_ = memfd_create("fss-stderr", MFD_CLOEXEC);
  if (captured_ >= 0 && captured_ <= STDERR_FILENO) {
    // Descriptors 0 to 2 were closed: keep the file clear of them.
    const int moved = fcntl(captured_, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    close(captured_);
    captured_ = moved;
  }
  if (captured_ < 0) return;
  saved_ = fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3);  // -1 (EBADF) when 2 was closed
  if (saved_ < 0 && errno != EBADF) {
    close(captured_);
    captured_ = -1;
    return;
  }
  if (dup2(captured_, STDERR_FILENO) < 0) {
    if (saved_ >= 0) close(saved_);
    close(captured_);
    saved_ = captured_ = -1;
  }
}

StderrCapture::~StderrCapture() { Finish(); }

std::string StderrCapture::Finish() {
  if (captured_ < 0) {
    if (lock_.owns_lock()) lock_.unlock();
    return {};
  }
  std::fflush(stderr);
  // Descriptor 2 back as it was: the saved duplicate, or closed again.
  if (saved_ >= 0) {
    dup2(saved_, STDERR_FILENO);
    close(saved_);
  } else {
    close(STDERR_FILENO);
  }
  saved_ = -1;
  std::string text;
  char buffer[4096];
  constexpr off_t kMaxBytes = 1 << 16;  // more says nothing the first 64 KiB do not
  for (off_t offset = 0; offset < kMaxBytes;) {
    const ssize_t n = pread(captured_, buffer, sizeof buffer, offset);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    offset += n;
  }
  close(captured_);
  captured_ = -1;
  lock_.unlock();  // descriptor 2 is the stream again: write_stderr may go on
  return text;
}

}  // namespace fss::detail
