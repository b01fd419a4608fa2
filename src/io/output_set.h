// Writing files so that a failure leaves nothing half written: one file
// through a temporary renamed into place, or a set of files staged together
// and renamed into place only once every one of them has been written.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace fss {

// One file of a set: its name in the output directory and its bytes, or
// the function that makes them when the file is staged.
struct OutputFile {
  std::string name;
  std::string bytes;
  // When set, `bytes` is unused: the file is made as it is written into the
  // staging directory and its bytes are freed once written, so a set of
  // large files never holds more of them in memory than the threads make at
  // once.
  std::function<std::string()> make;
  // The files of a higher rank are made first, the others in file order: the one that takes
  // longest to make starts first, rather than last with the other threads done and idle.
  int rank = 0;
};

// Writes `files` into `outdir` (created if missing) as one set: after a
// failure, a signal (SIGKILL included) or a concurrent run, `outdir` holds
// the old files or the new ones, never some of each (a run killed while
// publishing, a window of milliseconds, is completed by the next run into
// `outdir`: docs/testing.md, "Guarantees"). Other files in `outdir` are never
// touched.
// Refuses, before writing anything, to write into a path that is not a
// directory, to replace a directory, or to replace any of `protected_inputs`
// (compared as files: device and inode). Runs into one directory publish one
// after the other (an flock on `outdir`). Throws a runtime fss::Error on
// failure (a usage one for an empty `outdir`), with the old set in place and
// a directory it created removed. `stale_names` are names of files other
// runs write (with other options) that this set does not have: those in
// `outdir` belong to the old set and go with it when the new one is published.
// Files are made (OutputFile::make) and staged on up to `threads` threads
// (resolve_thread_count, parallel.h), each taking the next file by rank, then
// in file order; a file that cannot be made fails the set as a write would,
// the first such error (in file order) is the one thrown.
void write_output_set(const std::filesystem::path& outdir, const std::vector<OutputFile>& files,
                      const std::vector<std::string>& protected_inputs,
                      const std::vector<std::string>& stale_names = {}, int threads = 1);

// Writes `bytes` to `path` through a temporary file in the same directory
// renamed into place, so `path` is either untouched or complete: the same as
// write_file_safely (safe_write.h) without inputs to protect. Throws a
// runtime fss::Error naming the file on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace fss
