// A run's outputs published as one set (docs/testing.md, "Guarantees").
//
// 1. Stage: every file is written and fsync'ed into a new hidden directory
//    inside the output directory, ".fssim-stage-*", created with mode 1700
//    (the sticky bit, which umask leaves, marks it as fssim's from its
//    creation on), which holds an flock for as long as its run lives and a
//    marker file naming it as fssim's.
// 2. Commit: a manifest (".fssim-commit": the inode and name of every new
//    file) is renamed into the staging directory, which is then fsync'ed.
// 3. Publish, under an flock on the output directory itself: each new file
//    takes its name with renameat2(RENAME_EXCHANGE), which moves the old file
//    into the staging directory, or RENAME_NOREPLACE where there was none.
//    A failure half way exchanges back what was published: the old set is
//    whole again. Then the directory is fsync'ed and the staging directory,
//    holding the old files, removed.
// Before publishing, the same lock held, every staging directory of a run
// that is gone (its flock free) is dealt with: committed ones are published
// (or rolled back if that fails), the others removed. Which files are new is
// told by the manifest's inode numbers, so these steps can be redone at any
// point a run was killed. Only a directory that is provably fssim's is
// touched: marked by its mode, owned by this user, holding the marker file,
// and holding (and its manifest naming) only names of outputs; any other is
// left alone, even empty.
#include "io/output_set.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <optional>
#include <set>
#include <system_error>
#include <utility>

#include "core/parallel.h"
#include "fss/core/error.h"
#include "io/created_directories.h"
#include "io/safe_write.h"
#include "io/write_all.h"

namespace fss {

namespace {

using detail::write_all;

namespace fs = std::filesystem;

constexpr char kStagePrefix[] = ".fssim-stage-";
constexpr char kMarkerName[] = ".fssim-staging";
constexpr char kMarkerText[] = "staging directory of an fssim run: removed by the next run\n";
constexpr char kCommitName[] = ".fssim-commit";
constexpr char kCommitTemporary[] = ".fssim-commit.tmp";
// The mode of a staging directory: the sticky bit marks it as fssim's.
constexpr mode_t kStageMode = S_ISVTX | 0700;
// Largest manifest read: a few hundred bytes per output file.
constexpr std::size_t kMaxManifestBytes = std::size_t{1} << 20;

// A file descriptor closed on destruction.
class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  Fd(Fd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  Fd& operator=(Fd&& other) noexcept {
    std::swap(fd_, other.fd_);
    return *this;
  }
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

// A new file and its inode, as the manifest records them; inode 0: an
// output of another run the new set does not have, removed when it is
// published.
struct Entry {
  std::string name;
  ino_t inode = 0;
};

std::string error_text(int error) { return std::strerror(error); }

// flock that retries on a signal; 0 or the errno.
int lock_fd(int fd, int operation) {
  while (::flock(fd, operation) != 0) {
    if (errno != EINTR) return errno;
  }
  return 0;
}

// A file written but not yet synced: its descriptor, inode and name as shown in errors.
struct WrittenFile {
  Fd fd;
  ino_t inode = 0;
  std::string shown;
};

// Creates `name` in `dir_fd` (O_EXCL), writes `bytes` and starts their writeback without waiting
// for it (sync_file): the files of a set are then synced together, at the cost of about one
// sync, not one each. Throws a runtime fss::Error naming `shown` on failure.
WrittenFile write_new_file(int dir_fd, const std::string& name, const std::string& bytes,
                           const std::string& shown) {
  Fd fd(::openat(dir_fd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666));
  if (fd.get() < 0)
    throw_runtime_error("cannot write output '" + shown + "': " + error_text(errno));
  int error = write_all(fd.get(), bytes);
  struct stat st {};
  if (error == 0 && ::fstat(fd.get(), &st) != 0) error = errno;
  if (error != 0) throw_runtime_error("cannot write output '" + shown + "': " + error_text(error));
  // A hint only: where it fails or is not supported, sync_file's fsync does the whole work.
  ::sync_file_range(fd.get(), 0, 0, SYNC_FILE_RANGE_WRITE);
  return {std::move(fd), st.st_ino, shown};
}

// fsyncs a written file. Throws a runtime fss::Error naming it on failure.
void sync_file(const WrittenFile& file) {
  if (::fsync(file.fd.get()) != 0) {
    throw_runtime_error("cannot write output '" + file.shown + "': " + error_text(errno));
  }
}

// The inode of `name` in `dir_fd` (not following a symbolic link), 0 if none.
ino_t inode_of(int dir_fd, const std::string& name) {
  struct stat st {};
  if (::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return 0;
  return st.st_ino;
}

bool is_directory_at(int dir_fd, const std::string& name) {
  struct stat st {};
  return ::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISDIR(st.st_mode);
}

// Moves `name` from `from_fd` to `to_fd`: exchanged with the file already
// there, or moved where there is none. 0 or the errno.
int exchange_or_move(int from_fd, int to_fd, const std::string& name) {
  const char* n = name.c_str();
  if (::renameat2(from_fd, n, to_fd, n, RENAME_EXCHANGE) == 0) return 0;
  if (errno != ENOENT) return errno;
  return ::renameat2(from_fd, n, to_fd, n, RENAME_NOREPLACE) == 0 ? 0 : errno;
}

// Publishes every file of `manifest` still in the staging directory. Throws
// a runtime fss::Error naming the file that could not be published.
void publish_forward(int stage_fd, int out_fd, const std::vector<Entry>& manifest,
                     const fs::path& outdir) {
  for (const Entry& entry : manifest) {
    int error = 0;
    if (entry.inode == 0) {
      // Stale: moved out of the way, into the staging directory (never a
      // directory: that is not an output).
      if (inode_of(out_fd, entry.name) == 0 || inode_of(stage_fd, entry.name) != 0) continue;
      if (is_directory_at(out_fd, entry.name)) continue;
      if (::renameat2(out_fd, entry.name.c_str(), stage_fd, entry.name.c_str(), RENAME_NOREPLACE) !=
          0) {
        error = errno;
      }
    } else if (inode_of(stage_fd, entry.name) == entry.inode) {
      error = exchange_or_move(stage_fd, out_fd, entry.name);
    }
    if (error != 0) {
      throw_runtime_error("cannot replace '" + (outdir / entry.name).string() +
                          "': " + error_text(error));
    }
  }
}

// Undoes publish_forward: every published new file goes back to the staging
// directory, the old one it replaced (if any) back into place. Whether every
// file could be put back.
bool publish_backward(int stage_fd, int out_fd, const std::vector<Entry>& manifest) {
  bool ok = true;
  for (auto it = manifest.rbegin(); it != manifest.rend(); ++it) {
    const char* name = it->name.c_str();
    if (it->inode == 0) {
      if (inode_of(stage_fd, it->name) == 0 || inode_of(out_fd, it->name) != 0) continue;
      if (::renameat2(stage_fd, name, out_fd, name, RENAME_NOREPLACE) != 0) ok = false;
    } else if (inode_of(out_fd, it->name) == it->inode) {
      if (exchange_or_move(out_fd, stage_fd, it->name) != 0) ok = false;
    }
  }
  return ok;
}

// The names in the directory `dir_fd` but "." and "..", or nullopt if it
// cannot be listed.
std::optional<std::vector<std::string>> names_in(int dir_fd) {
  const int copy = ::dup(dir_fd);
  DIR* dir = copy >= 0 ? ::fdopendir(copy) : nullptr;
  if (dir == nullptr) {
    if (copy >= 0) ::close(copy);
    return std::nullopt;
  }
  ::rewinddir(dir);  // the copy shares its position with `dir_fd`: listed before, it is at the end
  std::vector<std::string> names;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  ::closedir(dir);
  return names;
}

// Removes every entry of the staging directory `stage_name` (files only: it
// holds nothing else), then the directory itself.
void remove_stage(int out_fd, int stage_fd, const std::string& stage_name) {
  if (const auto names = names_in(stage_fd)) {
    // The commit first: a removal killed half way must not be published by
    // recover(). The marker last: until it goes, the directory is known as ours.
    ::unlinkat(stage_fd, kCommitName, 0);
    for (const std::string& name : *names) {
      if (name != kMarkerName) ::unlinkat(stage_fd, name.c_str(), 0);
    }
    ::unlinkat(stage_fd, kMarkerName, 0);
  }
  ::unlinkat(out_fd, stage_name.c_str(), AT_REMOVEDIR);
}

// The manifest as written to .fssim-commit: "INODE NAME" lines.
std::string format_manifest(const std::vector<Entry>& manifest) {
  std::string text;
  for (const Entry& entry : manifest) {
    text += std::to_string(entry.inode) + " " + entry.name + "\n";
  }
  return text;
}

// The names a staging directory may hold: this call's outputs, the stale
// names, and the marker and manifest files.
using KnownNames = std::set<std::string>;

bool is_plain_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         name.find_first_of(std::string("/\0", 2)) == std::string::npos;
}

// The regular file `name` of `dir_fd` (not following a symbolic link, never
// waiting on a FIFO), at most `max_bytes`; nullopt if missing (*missing
// set), not a regular file, larger or unreadable.
std::optional<std::string> read_small_file(int dir_fd, const char* name, std::size_t max_bytes,
                                           bool* missing) {
  Fd fd(::openat(dir_fd, name, O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK));
  if (missing != nullptr) *missing = fd.get() < 0 && errno == ENOENT;
  struct stat st {};
  if (fd.get() < 0 || ::fstat(fd.get(), &st) != 0 || !S_ISREG(st.st_mode) ||
      static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    return std::nullopt;
  }
  std::string text;
  char buffer[4096];
  for (ssize_t got; (got = ::read(fd.get(), buffer, sizeof buffer)) != 0;) {
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 || text.size() + static_cast<std::size_t>(got) > max_bytes) return std::nullopt;
    text.append(buffer, static_cast<std::size_t>(got));
  }
  return text;
}

// The manifest of the staging directory `stage_fd`: empty if it was never
// committed; nullopt if it cannot be trusted: unreadable, a line not
// "INODE NAME", or a name that is not a plain file name of `known`.
std::optional<std::vector<Entry>> read_manifest(int stage_fd, const KnownNames& known) {
  bool missing = false;
  const std::optional<std::string> text =
      read_small_file(stage_fd, kCommitName, kMaxManifestBytes, &missing);
  if (!text)
    return missing ? std::optional<std::vector<Entry>>(std::vector<Entry>{}) : std::nullopt;
  std::vector<Entry> manifest;
  std::size_t begin = 0;
  while (begin < text->size()) {
    const std::size_t end = text->find('\n', begin);
    if (end == std::string::npos) return std::nullopt;
    const std::string line = text->substr(begin, end - begin);
    begin = end + 1;
    const std::size_t space = line.find(' ');
    Entry entry;
    const char* first = line.data();
    const char* last = line.data() + (space == std::string::npos ? 0 : space);
    const auto [ptr, ec] = std::from_chars(first, last, entry.inode);
    if (space == std::string::npos || space == 0 || ec != std::errc() || ptr != last) {
      return std::nullopt;
    }
    entry.name = line.substr(space + 1);
    if (!is_plain_name(entry.name) || known.count(entry.name) == 0) return std::nullopt;
    manifest.push_back(std::move(entry));
  }
  return manifest;
}

// Whether `st` is of a staging directory fssim created: a directory of
// kStageMode owned by this user.
bool is_marked_stage(const struct stat& st) {
  return S_ISDIR(st.st_mode) && (st.st_mode & 07777) == kStageMode && st.st_uid == ::geteuid();
}

// Whether every entry of the staging directory `stage_fd` is one fssim puts
// there: an output name of `known`, the marker or the manifest.
bool holds_only_known_names(int stage_fd, const KnownNames& known) {
  const auto names = names_in(stage_fd);
  if (!names) return false;
  return std::all_of(names->begin(), names->end(), [&](const std::string& name) {
    return name == kMarkerName || name == kCommitName || name == kCommitTemporary ||
           known.count(name) != 0;
  });
}

// Whether `stage_name` in `out_fd` is a staging directory of fssim's (marked
// by its mode, owned by this user) left by a run that is gone, holding the
// marker file and only names of `known`; if so, its open, locked descriptor.
// A marked one without its marker (killed as it was created or removed) is
// removed if empty; an unmarked one is never touched.
Fd open_abandoned_stage(int out_fd, const std::string& stage_name, const KnownNames& known) {
  Fd fd(::openat(out_fd, stage_name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  struct stat st {};
  if (fd.get() < 0 || ::fstat(fd.get(), &st) != 0 || !is_marked_stage(st)) return Fd();
  if (lock_fd(fd.get(), LOCK_EX | LOCK_NB) != 0) return Fd();  // its run is alive
  bool missing = false;
  const std::optional<std::string> marker =
      read_small_file(fd.get(), kMarkerName, sizeof kMarkerText, &missing);
  if (missing) {
    ::unlinkat(out_fd, stage_name.c_str(), AT_REMOVEDIR);  // only if empty
    return Fd();
  }
  if (!marker || *marker != kMarkerText || !holds_only_known_names(fd.get(), known)) return Fd();
  return fd;
}

// Completes or removes what killed runs left in the output directory: a
// committed set is published (rolled back if it cannot be), anything else
// staged is removed. Called with the output directory locked.
void recover(int out_fd, const fs::path& outdir, const KnownNames& known) {
  std::vector<std::string> stages;
  for (const std::string& name : names_in(out_fd).value_or(std::vector<std::string>{})) {
    if (name.rfind(kStagePrefix, 0) == 0) stages.push_back(name);
  }
  for (const std::string& name : stages) {
    const Fd stage = open_abandoned_stage(out_fd, name, known);
    if (stage.get() < 0) continue;
    const std::optional<std::vector<Entry>> read = read_manifest(stage.get(), known);
    if (!read) continue;  // not provably fssim's: left alone
    const std::vector<Entry>& manifest = *read;
    try {
      publish_forward(stage.get(), out_fd, manifest, outdir);
    } catch (const Error&) {
      if (!publish_backward(stage.get(), out_fd, manifest)) continue;  // left for later
    }
    ::fsync(out_fd);
    remove_stage(out_fd, stage.get(), name);
  }
}

// A staging directory of this run, locked while it lives.
struct Stage {
  Fd fd;
  std::string name;
  std::vector<Entry> manifest;
};

// Creates and locks this run's staging directory, the output directory
// locked meanwhile: recover() never finds it unlocked.
Stage create_stage(int out_fd, const fs::path& outdir) {
  static int counter = 0;
  const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
  const auto fail = [&](int error) {
    ::flock(out_fd, LOCK_UN);
    throw_runtime_error("cannot write into output directory '" + outdir.string() +
                        "': " + error_text(error));
  };
  if (const int error = lock_fd(out_fd, LOCK_EX); error != 0) fail(error);
  for (int attempt = 0;; ++attempt) {
    const std::string name = kStagePrefix + std::to_string(::getpid()) + "-" + std::to_string(now) +
                             "-" + std::to_string(counter++);
    if (::mkdirat(out_fd, name.c_str(), kStageMode) != 0) {
      if (errno == EEXIST && attempt < 100) continue;
      fail(errno);
    }
    Stage stage{Fd(::openat(out_fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)),
                name,
                {}};
    if (stage.fd.get() < 0 || lock_fd(stage.fd.get(), LOCK_EX) != 0) {
      const int error = errno;
      ::unlinkat(out_fd, name.c_str(), AT_REMOVEDIR);
      fail(error);
    }
    // Linux keeps the sticky bit of mkdir's mode; where a file system drops
    // it, it is set now. A directory left unmarked still serves this run,
    // which removes it itself; only its recovery by a later run is lost.
    struct stat st {};
    if (::fstat(stage.fd.get(), &st) == 0 && !is_marked_stage(st)) {
      ::fchmod(stage.fd.get(), kStageMode);
    }
    ::flock(out_fd, LOCK_UN);
    return stage;
  }
}

// The order in which the files are made: by decreasing rank, in file order within a rank.
std::vector<int> making_order(const std::vector<OutputFile>& files) {
  std::vector<int> order(files.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return files[static_cast<std::size_t>(a)].rank > files[static_cast<std::size_t>(b)].rank;
  });
  return order;
}

// Writes every file (made now when it has a maker, on `threads` threads), the marker and the
// manifest into the staging directory, then fsyncs them all before the manifest takes its name,
// which the directory's fsync makes durable.
void stage_and_commit(Stage& stage, const fs::path& outdir, const std::vector<OutputFile>& files,
                      const std::vector<std::string>& stale_names, int threads) {
  std::vector<WrittenFile> written(files.size() + 2);
  written[0] =
      write_new_file(stage.fd.get(), kMarkerName, kMarkerText, (outdir / kMarkerName).string());
  parallel_for_each(making_order(files), threads, [&](int i) {
    const OutputFile& file = files[static_cast<std::size_t>(i)];
    const std::string made = file.make ? file.make() : std::string();
    written[static_cast<std::size_t>(i) + 1] = write_new_file(
        stage.fd.get(), file.name, file.make ? made : file.bytes, (outdir / file.name).string());
  });
  for (std::size_t i = 0; i < files.size(); ++i)
    stage.manifest.push_back({files[i].name, written[i + 1].inode});
  for (const std::string& name : stale_names) {
    const bool in_set = std::any_of(files.begin(), files.end(),
                                    [&](const OutputFile& file) { return file.name == name; });
    if (!in_set) stage.manifest.push_back({name, 0});
  }
  written.back() = write_new_file(stage.fd.get(), kCommitTemporary, format_manifest(stage.manifest),
                                  (outdir / kCommitName).string());
  for (const WrittenFile& file : written) sync_file(file);
  if (::renameat(stage.fd.get(), kCommitTemporary, stage.fd.get(), kCommitName) != 0 ||
      ::fsync(stage.fd.get()) != 0) {
    throw_runtime_error("cannot write into output directory '" + outdir.string() +
                        "': " + error_text(errno));
  }
}

// Creates `outdir` if missing; the directories created, outermost first.
std::vector<fs::path> create_output_directory(const fs::path& outdir) {
  std::error_code ec;
  if (fs::exists(outdir, ec) && !fs::is_directory(outdir, ec)) {
    throw_runtime_error("output directory '" + outdir.string() + "' exists and is not a directory");
  }
  if (fs::is_directory(outdir, ec)) return {};
  std::vector<fs::path> created = detail::create_directories_listed(outdir, ec);
  if (ec) {
    detail::remove_created_directories(created);
    throw_runtime_error("cannot create output directory '" + outdir.string() +
                        "': " + ec.message());
  }
  return created;
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
  if (fs::is_directory(fs::symlink_status(target, ec))) {
    throw_runtime_error("cannot write output '" + target.string() + "': it is a directory");
  }
}

void check_targets(const fs::path& outdir, const std::vector<OutputFile>& files,
                   const std::vector<std::string>& protected_inputs) {
  for (const OutputFile& file : files) check_target(outdir / file.name, protected_inputs);
}

// Publishes the committed `stage` into `out_fd`, which the caller has
// locked. On a failure, puts the old set back and throws; `*half_published`
// tells when even that failed (the staging directory must then stay for the
// next run's recover()).
void publish(Stage& stage, int out_fd, const fs::path& outdir, bool* half_published) {
  try {
    publish_forward(stage.fd.get(), out_fd, stage.manifest, outdir);
  } catch (const Error& e) {
    if (!publish_backward(stage.fd.get(), out_fd, stage.manifest)) {
      *half_published = true;
      throw_runtime_error(std::string(e.what()) +
                          "; some old outputs could not be put back: the next run into '" +
                          outdir.string() + "' completes the new set");
    }
    throw;
  }
  if (::fsync(out_fd) != 0) {
    throw_runtime_error("cannot write into output directory '" + outdir.string() +
                        "': " + error_text(errno));
  }
}

KnownNames known_names(const std::vector<OutputFile>& files,
                       const std::vector<std::string>& stale_names) {
  KnownNames known(stale_names.begin(), stale_names.end());
  for (const OutputFile& file : files) known.insert(file.name);
  return known;
}

// The stale names whose files in `outdir` go with the old set: all but an
// input of this run (an input named like an output is never removed).
std::vector<std::string> retired_names(const fs::path& outdir,
                                       const std::vector<std::string>& stale_names,
                                       const std::vector<std::string>& protected_inputs) {
  std::vector<std::string> retired;
  for (const std::string& name : stale_names) {
    const bool input =
        std::any_of(protected_inputs.begin(), protected_inputs.end(),
                    [&](const std::string& in) { return same_file(outdir / name, in); });
    if (!input) retired.push_back(name);
  }
  return retired;
}

// Stages, commits and publishes `files`; the output directory is open as
// `out_fd`. A failure before publishing removes what was staged.
void write_set(int out_fd, const fs::path& outdir, const std::vector<OutputFile>& files,
               const std::vector<std::string>& protected_inputs,
               const std::vector<std::string>& stale_names, int threads) {
  Stage stage = create_stage(out_fd, outdir);
  bool half_published = false;
  try {
    stage_and_commit(stage, outdir, files, retired_names(outdir, stale_names, protected_inputs),
                     threads);
    if (const int error = lock_fd(out_fd, LOCK_EX); error != 0) {
      throw_runtime_error("cannot lock output directory '" + outdir.string() +
                          "': " + error_text(error));
    }
    recover(out_fd, outdir, known_names(files, stale_names));
    check_targets(outdir, files, protected_inputs);
    publish(stage, out_fd, outdir, &half_published);
  } catch (...) {
    // Left in place only when half published and not put back: recover()
    // of the next run completes it.
    if (!half_published) remove_stage(out_fd, stage.fd.get(), stage.name);
    throw;
  }
  remove_stage(out_fd, stage.fd.get(), stage.name);
}

}  // namespace

void write_output_set(const fs::path& outdir, const std::vector<OutputFile>& files,
                      const std::vector<std::string>& protected_inputs,
                      const std::vector<std::string>& stale_names, int threads) {
  if (outdir.empty()) throw_usage_error("the output directory must not be an empty path");
  check_targets(outdir, files, protected_inputs);
  const std::vector<fs::path> created = create_output_directory(outdir);
  try {
    const Fd out(::open(outdir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (out.get() < 0) {
      throw_runtime_error("cannot open output directory '" + outdir.string() +
                          "': " + error_text(errno));
    }
    write_set(out.get(), outdir, files, protected_inputs, stale_names, threads);
  } catch (...) {
    // A failed run leaves no directory it created (each removed only empty).
    detail::remove_created_directories(created);
    throw;
  }
}

namespace detail {

std::vector<fs::path> create_directories_listed(const fs::path& dir, std::error_code& ec) {
  ec.clear();
  // The missing ones, innermost first (a trailing '/' names no directory).
  std::vector<fs::path> missing;
  for (fs::path p = dir.has_filename() ? dir : dir.parent_path(); !p.empty(); p = p.parent_path()) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) == 0 || errno != ENOENT) break;
    missing.push_back(p);
    if (!p.has_parent_path() || p.parent_path() == p) break;
  }
  std::vector<fs::path> created;
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) == 0) {
      created.push_back(*it);
    } else if (errno != EEXIST) {
      ec.assign(errno, std::generic_category());
      return created;
    }
  }
  if (!fs::is_directory(dir, ec) && !ec) ec = std::make_error_code(std::errc::not_a_directory);
  return created;
}

void remove_created_directories(const std::vector<fs::path>& created) {
  for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());
}

}  // namespace detail

void write_file_atomically(const fs::path& path, const std::string& bytes) {
  write_file_safely(path, bytes);
}

}  // namespace fss
