#include "fss/io/output_set.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "fss/core/error.h"

namespace fss {

namespace {

namespace fs = std::filesystem;

// A staged file and where it goes.
struct Staged {
  fs::path temporary;
  fs::path target;
};

// Writes all of `bytes` to `fd`; 0 or the errno of the failure.
int write_all(int fd, const std::string& bytes) {
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

// Creates a new file next to `target`, under a name no other file has
// (O_EXCL: nothing existing is ever replaced or removed), writes `bytes` into
// it and returns its path. On failure, removes it and throws a runtime fss::Error.
fs::path stage(const fs::path& target, const std::string& bytes) {
  const fs::path dir = target.parent_path();
  const std::string prefix =
      std::string(".") + target.filename().string() + ".fssim-" + std::to_string(::getpid()) + "-";
  for (int attempt = 0;; ++attempt) {
    fs::path temporary = dir / (prefix + std::to_string(attempt) + ".tmp");
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 100) continue;
      throw_runtime_error("cannot write output '" + target.string() +
                          "': cannot create a file in '" + dir.string() +
                          "': " + std::strerror(errno));
    }
    int error = write_all(fd, bytes);
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) {
      ::unlink(temporary.c_str());
      throw_runtime_error("cannot write output '" + target.string() + "': " + std::strerror(error));
    }
    return temporary;
  }
}

// Renames every staged file into place, in order; on a failure, removes the
// temporary files not yet moved and throws.
void rename_all(const std::vector<Staged>& staged) {
  std::error_code ec;
  for (std::size_t i = 0; i < staged.size(); ++i) {
    fs::rename(staged[i].temporary, staged[i].target, ec);
    if (ec) {
      const std::string message = "cannot move '" + staged[i].temporary.string() + "' to '" +
                                  staged[i].target.string() + "': " + ec.message();
      for (std::size_t j = i; j < staged.size(); ++j) fs::remove(staged[j].temporary, ec);
      throw_runtime_error(message);
    }
  }
}

void create_output_directory(const fs::path& outdir) {
  std::error_code ec;
  if (fs::exists(outdir, ec) && !fs::is_directory(outdir, ec)) {
    throw_runtime_error("output directory '" + outdir.string() + "' exists and is not a directory");
  }
  fs::create_directories(outdir, ec);
  if (ec) {
    throw_runtime_error("cannot create output directory '" + outdir.string() +
                        "': " + ec.message());
  }
}

// Throws if writing `target` would replace one of `protected_inputs` or a
// directory.
void check_target(const fs::path& target, const std::vector<std::string>& protected_inputs) {
  std::error_code ec;
  for (const std::string& input : protected_inputs) {
    if (fs::exists(target, ec) && fs::exists(input, ec) && fs::equivalent(target, input, ec)) {
      throw_runtime_error("refusing to overwrite the input '" + input + "' with output '" +
                          target.string() + "': choose another --outdir");
    }
  }
  if (fs::is_directory(target, ec)) {
    throw_runtime_error("cannot write output '" + target.string() + "': it is a directory");
  }
}

// Stages every file of `files`; on a failure, removes what was staged and
// rethrows.
std::vector<Staged> stage_all(const fs::path& outdir, const std::vector<OutputFile>& files) {
  std::vector<Staged> staged;
  staged.reserve(files.size());
  try {
    for (const OutputFile& file : files) {
      fs::path target = outdir / file.name;
      fs::path temporary = stage(target, file.bytes);
      staged.push_back({std::move(temporary), std::move(target)});
    }
  } catch (...) {
    std::error_code ec;
    for (const Staged& file : staged) fs::remove(file.temporary, ec);
    throw;
  }
  return staged;
}

}  // namespace

void write_output_set(const fs::path& outdir, const std::vector<OutputFile>& files,
                      const std::vector<std::string>& protected_inputs) {
  if (outdir.empty()) throw_usage_error("the output directory must not be an empty path");
  create_output_directory(outdir);
  for (const OutputFile& file : files) check_target(outdir / file.name, protected_inputs);
  // Stage every file, then rename them into place: a failure before the
  // renames leaves the directory as it was.
  rename_all(stage_all(outdir, files));
}

void write_file_atomically(const fs::path& path, const std::string& bytes) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    throw_runtime_error("cannot write '" + path.string() + "': it is a directory");
  }
  const fs::path target = path.has_parent_path() ? path : "./" / path;
  rename_all({{stage(target, bytes), target}});
}

}  // namespace fss
