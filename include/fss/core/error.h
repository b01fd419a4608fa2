// fss error reporting: every failure is an fss::Error carrying a one-line,
// self-contained message that names the file, option or value at fault and
// what was expected. The kind tells a front end how to exit.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace fss {

enum class ErrorKind {
  kUsage,    // a parameter or a combination of parameters is not acceptable
  kRuntime,  // a file could not be read or written, or its content is bad
  kLimit,    // the run would need more memory than the limit it was given
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message);
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

[[noreturn]] void throw_usage_error(const std::string& message);
[[noreturn]] void throw_runtime_error(const std::string& message);
[[noreturn]] void throw_limit_error(const std::string& message);

// "1.5 GiB", "800.0 MiB", "12.0 KiB" (binary units, as --max-memory reads them).
std::string format_bytes(double bytes);

// A number as printf("%.*g") writes it with `significant_digits` digits
// ("nan", never "-nan"; "inf", "-inf"): the default is printf("%g"), for
// messages; 17 digits give back the same double.
std::string format_number(double value, int significant_digits = 6);

// `text` with control characters (a newline in a file name, a terminal
// escape) written as \xNN, so that a message stays on one readable line.
std::string escape_control_characters(std::string_view text);

}  // namespace fss
