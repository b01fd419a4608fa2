// Pieces shared by fssim's main command and its subcommands: exit codes,
// option validators, error reporting and atomic file writes.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

namespace fssim {

inline constexpr int kExitRuntime = 1;
inline constexpr int kExitUsage = 2;

// CLI11 validator for finite numbers (CLI11 accepts "nan" and "inf").
inline const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) {
        return "value " + text + " is not a finite number";
      }
      return {};
    },
    "FINITE", "finite");

inline const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      double value = 0.0;
      if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0)) {
        return "value " + text + " must be > 0";
      }
      return {};
    },
    "POSITIVE", "positive");

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

// Writes `bytes` to `path` through a temporary file in the same directory
// renamed into place, so that `path` is either untouched or complete. Throws a
// runtime fss::Error naming the file on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

// A number as printf("%g") writes it.
std::string format_number(double value);

}  // namespace fssim
