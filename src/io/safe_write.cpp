#include "io/safe_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "fss/core/error.h"
#include "io/created_directories.h"
#include "io/write_all.h"

namespace fss {

namespace {

using detail::write_all;

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& why) {
  throw_runtime_error("cannot write '" + path.string() + "': " + why);
}

// Whether `path`, made absolute and normal, lies under /dev or /proc, where
// names stand for devices and open files rather than for files to replace.
bool is_under_dev_or_proc(const fs::path& path) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  const auto first = ++absolute.begin();
  return !ec && first != absolute.end() && (*first == "dev" || *first == "proc");
}

// The descriptor N that /dev/stdout, /dev/stderr, /dev/fd/N or
// /proc/self/fd/N names; -1 for any other path.
int open_descriptor_named(const fs::path& path) {
  const std::string text = path.lexically_normal().string();
  if (text == "/dev/stdout") return STDOUT_FILENO;
  if (text == "/dev/stderr") return STDERR_FILENO;
  for (const std::string prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    if (text.rfind(prefix, 0) != 0 || text.size() == prefix.size() ||
        text.size() > prefix.size() + 6) {
      continue;
    }
    int fd = 0;
    for (std::size_t i = prefix.size(); i < text.size(); ++i) {
      if (text[i] < '0' || text[i] > '9') return -1;
      fd = 10 * fd + (text[i] - '0');
    }
    return fd;
  }
  return -1;
}

// Writes `bytes` into the existing `path`: through the descriptor it names
// (open_descriptor_named), with the position and mode the shell gave it, or
// opened anew without creating or truncating anything.
void write_in_place(const fs::path& path, std::string_view bytes) {
  if (const int named = open_descriptor_named(path); named >= 0) {
    if (const int error = write_all(named, bytes); error != 0) fail(path, std::strerror(error));
    return;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) fail(path, std::strerror(errno));
  int error = write_all(fd, bytes);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) fail(path, std::strerror(error));
}

// Replaces (or creates) the regular file `target` through a temporary in its
// directory; `mode` is given to the new file when `keep_mode`.
void replace_atomically(const fs::path& target, std::string_view bytes, bool keep_mode,
                        mode_t mode) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string prefix = ".";
  prefix += target.filename().string();
  prefix += ".fssim-" + std::to_string(::getpid()) + "-";
  for (int attempt = 0;; ++attempt) {
    const fs::path temporary = dir / (prefix + std::to_string(attempt) + ".tmp");
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 100) continue;
      fail(target, "cannot create a file in '" + dir.string() + "': " + std::strerror(errno));
    }
    int error = write_all(fd, bytes);
    if (error == 0 && keep_mode && ::fchmod(fd, mode & 07777) != 0) error = errno;
    if (error == 0 && ::fsync(fd) != 0) error = errno;
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error == 0 && ::rename(temporary.c_str(), target.c_str()) != 0) error = errno;
    if (error != 0) {
      ::unlink(temporary.c_str());
      fail(target, std::strerror(error));
    }
    return;
  }
}

void check_not_an_input(const fs::path& path, const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    if (same_file(path, input)) {
      throw_runtime_error("refusing to write '" + path.string() + "' over the input '" + input +
                          "'");
    }
  }
}

}  // namespace

bool same_file(const fs::path& a, const fs::path& b) {
  struct stat sa {};
  struct stat sb {};
  const bool a_exists = ::stat(a.c_str(), &sa) == 0;
  const bool b_exists = ::stat(b.c_str(), &sb) == 0;
  if (a_exists && b_exists) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (a_exists != b_exists) return false;
  std::error_code ea;
  std::error_code eb;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ea), ea);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
  return !ea && !eb && ca == cb;
}

void write_file_safely(const fs::path& path, std::string_view bytes,
                       const std::vector<std::string>& inputs) {
  if (path.empty()) throw_usage_error("the output path must not be empty");
  check_not_an_input(path, inputs);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) fail(path, std::strerror(errno));
    struct stat link {};
    if (::lstat(path.c_str(), &link) == 0) fail(path, "it is a symbolic link to a missing file");
    if (is_under_dev_or_proc(path)) fail(path, "no such device or open file");
    replace_atomically(path, bytes, false, 0);
    return;
  }
  if (S_ISDIR(st.st_mode)) fail(path, "it is a directory");
  if (S_ISBLK(st.st_mode) || S_ISSOCK(st.st_mode)) {
    fail(path, "it is a block device or a socket, not a file");
  }
  if (!S_ISREG(st.st_mode) || is_under_dev_or_proc(path)) {
    write_in_place(path, bytes);
    return;
  }
  std::error_code ec;
  const fs::path target = fs::canonical(path, ec);  // a symbolic link stays one
  replace_atomically(ec ? path : target, bytes, true, st.st_mode);
}

// write_file_safely, with the missing folders of `path` created first and removed again when
// the write fails.
void write_file_in_folders(const fs::path& path, std::string_view bytes,
                           const std::vector<std::string>& inputs) {
  if (path.empty() || !path.has_parent_path()) {
    write_file_safely(path, bytes, inputs);
    return;
  }
  std::error_code ec;
  const std::vector<fs::path> created = detail::create_directories_listed(path.parent_path(), ec);
  try {
    if (ec) {
      fail(path, "cannot create its folder '" + path.parent_path().string() + "': " + ec.message());
    }
    write_file_safely(path, bytes, inputs);
  } catch (...) {
    detail::remove_created_directories(created);
    throw;
  }
}

}  // namespace fss
