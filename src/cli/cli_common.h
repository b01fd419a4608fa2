// Pieces shared by fssim's commands: exit codes, option validators, the one
// error reporter and atomic file writes.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/outputs.h"
#include "fss/model/sensor.h"
#include "io/output_set.h"

namespace fssim {

// Exit statuses of every command.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitRuntime = 1;  // a file, the memory limit, anything at run time
inline constexpr int kExitUsage = 2;    // the command line asks for something not acceptable

// CLI11 validators, made on demand so that nothing can throw during static
// initialization. Their messages follow the option's name: "--dt: value 0
// must be > 0".
// A finite number (CLI11 itself accepts "nan" and "inf").
CLI::Validator finite();
// A number > 0.
CLI::Validator positive();
// dt and snr of the simulation: finite, > 0 and within the library's range
// (fss::scale_rule).
CLI::Validator scale();
// An integer of at least `minimum`, with a short message (CLI11's own range
// checks print the largest double in full).
CLI::Validator at_least(long long minimum);
// An integer in [minimum, maximum].
CLI::Validator integer_in(long long minimum, long long maximum);
// Decimal digits of an unsigned 64-bit integer (CLI11 itself wraps "-1" and
// saturates values above 2^64 - 1 without a word).
CLI::Validator seed_value();
// --rmse-margin: a number of columns in [0, kMaxMarginColumns], or "auto" (rewritten to
// kRmseMarginAuto); with allow_default, also -1 (the paper's 3B, kRmseMarginDefault).
CLI::Validator rmse_margin_value(bool allow_default);
// A path that is not empty.
CLI::Validator not_empty();

// Adds option `name` to `app`, bound to `value` and checked by `validator`,
// its default shown in --help.
template <typename T>
CLI::Option* add_checked_option(CLI::App& app, const std::string& name, T& value,
                                const std::string& description, const CLI::Validator& validator) {
  return app.add_option(name, value, description)->check(validator)->capture_default_str();
}

// "fssim code analyze --help": the help command of the deepest subcommand
// selected on the command line, for error messages.
std::string help_hint(const CLI::App& app);

// The first option of `app` itself (not of a subcommand) that was given on the
// command line, such as "--velocity"; empty if none. Help and version flags
// are not counted.
std::string first_given_option(const CLI::App& app);

// The one error reporter: "fssim: error: MESSAGE" on stderr, control
// characters escaped so that the message stays on one line.
void report_error(std::string_view message);

// What run_reporting_errors adds to a message.
struct ErrorContext {
  // Appended to an error of kind kLimit, e.g. " (raise it with --max-memory)".
  std::string limit_hint;
  // What the command is doing, for a failure that does not say it: "out of
  // memory while ACTIVITY", "MESSAGE (while ACTIVITY)". Empty: nothing added.
  std::string activity;
};

// Runs `body` and turns an exception into one reported error and the exit
// status: kExitUsage for a usage fss::Error, kExitRuntime otherwise. `context`
// (may be null) is read when the exception arrives, so the body may update it.
int run_reporting_errors(const std::function<int()>& body, const ErrorContext* context = nullptr);

// Whether `path` is "-", standard output.
inline bool is_stdout(const std::string& path) { return path == "-"; }

// Writes a command's output file: "-" is standard output, anything else goes
// through fss::write_file_safely (atomic, never over one of `inputs`, a
// device or FIFO written in place).
void write_output(const std::string& path, std::string_view bytes,
                  const std::vector<std::string>& inputs = {});

// The sensor options (docs/method.md §10) of the commands that take them
// (the simulation, sweep, campaign, code analyze and optimize): one rule and
// one wording for their errors.
// Refuses an ADC gain without an ADC (`adc_bits` 0): "--adc-gain: needs
// --adc-bits (without an ADC there are no counts)".
void check_adc_gain(bool adc_gain_given, int adc_bits);
// Throws the usage error of an invalid `sensor` (SensorModel::IsValid), its
// field named as the option that sets it: "--read-noise: value -1 must be
// finite and >= 0".
void check_sensor_options(const fss::SensorModel& sensor);

// Flushes standard output and checks both standard streams, for the end of
// main(): a write that failed (a full disk, a closed pipe, /dev/full) turns
// `status` 0 into kExitRuntime, reported on stderr where it still works.
int check_standard_streams(int status);

using fss::format_exact;           // fss/core/error.h
using fss::format_number;          // fss/core/error.h
using fss::write_file_atomically;  // io/output_set.h

}  // namespace fssim
