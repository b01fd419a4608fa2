// Pieces shared by fssim's main command and its subcommands: exit codes,
// option validators, error reporting and atomic file writes.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include "fss/core/error.h"
#include "fss/io/outputs.h"

namespace fssim {

inline constexpr int kExitRuntime = 1;
inline constexpr int kExitUsage = 2;

// CLI11 validators, made on demand so that nothing can throw during static
// initialization: finite numbers (CLI11 itself accepts "nan" and "inf"), and
// numbers > 0.
CLI::Validator finite();
CLI::Validator positive();

// Integer option of at least `minimum`, with a short message (CLI11's own
// range checks print the largest double in full).
CLI::Validator at_least(long long minimum);

// "fssim code analyze --help": the help command of the deepest subcommand
// selected on the command line, for error messages.
std::string help_hint(const CLI::App& app);

// The first option of `app` itself (not of a subcommand) that was given on the
// command line, such as "--velocity"; empty if none. Help and version flags
// are not counted.
std::string first_given_option(const CLI::App& app);

// Runs `body` and turns an exception into one "fssim: error: ..." line on
// stderr and the exit status: 2 for a usage fss::Error, 1 otherwise.
int run_reporting_errors(const std::function<int()>& body);

using fss::format_number;          // fss/error.h
using fss::write_file_atomically;  // fss/outputs.h

}  // namespace fssim
