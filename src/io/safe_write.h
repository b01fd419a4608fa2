// Writing one output file so that nothing is lost: a file is replaced
// atomically (a hidden temporary in its directory, fsync'ed, renamed over
// it), never over an input, and a device, FIFO or /proc/self/fd/N is written
// in place, never replaced by a regular file (docs/testing.md, "Guarantees").
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fss {

// Whether `a` and `b` name one file: the same device and inode when both
// exist, else the same path once made absolute, normal and free of symbolic
// links (std::filesystem::weakly_canonical).
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// Writes `bytes` to `path`:
// - missing, or a regular file (through any symbolic links, which stay):
//   written to a new hidden file in the same directory, fsync'ed, renamed
//   into place (keeping the old file's permissions); a failure leaves the
//   old file as it was and no temporary behind;
// - a character device or FIFO, or any path under /dev or /proc (such as
//   /dev/stdout or /proc/self/fd/1): opened and written in place;
// - a directory, a block device, a socket or a dangling symbolic link:
//   refused.
// Refuses, before writing anything, when `path` is the same file (same_file)
// as one of `inputs`. Throws a runtime fss::Error naming `path` on failure.
void write_file_safely(const std::filesystem::path& path, std::string_view bytes,
                       const std::vector<std::string>& inputs = {});

// write_file_safely into folders created when missing (removed again if the write fails): the
// single-file outputs of the command line (sweep -o out/runs/x.csv).
void write_file_in_folders(const std::filesystem::path& path, std::string_view bytes,
                           const std::vector<std::string>& inputs = {});

}  // namespace fss
