// Writing files so that a failure leaves nothing half written: one file
// through a temporary renamed into place, or a set of files staged together
// and renamed into place only once every one of them has been written.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace fss {

// One file of a set: its name in the output directory and its bytes.
struct OutputFile {
  std::string name;
  std::string bytes;
};

// Writes `files` into `outdir` (created if missing). Refuses, before writing
// anything, to write into a path that is not a directory, to replace a
// directory, or to replace any of `protected_inputs` (spelled any way).
// Each file is first written under a new hidden name in `outdir` and renamed
// into place, in order, only once all are complete. Throws a runtime
// fss::Error on failure (a usage one for an empty `outdir`), after removing
// whatever it staged: existing files are never touched then.
void write_output_set(const std::filesystem::path& outdir, const std::vector<OutputFile>& files,
                      const std::vector<std::string>& protected_inputs);

// Writes `bytes` to `path` through a temporary file in the same directory
// renamed into place, so `path` is either untouched or complete. Throws a
// runtime fss::Error naming the file on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace fss
