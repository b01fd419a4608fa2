// fss::Error, which every failure throws: a one-line message naming the file, option or value
// at fault and what was expected; its kind tells a front end how to exit.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

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

// `needed` and `limit` as format_bytes writes them, with as many more decimals as it takes to
// write two different sizes differently: the pair for "needs A, over the limit of B".
std::pair<std::string, std::string> format_bytes_distinct(double needed, double limit);

// Throws the limit fss::Error "<subject> needs about <needed> of memory, more
// than the memory limit of <limit>" (sizes by format_bytes_distinct).
[[noreturn]] void throw_memory_limit_error(const std::string& subject, std::size_t needed,
                                           std::size_t limit);

// A number exactly, for messages: the shortest digits that read back as the same double, laid
// out as printf("%g") lays them out ("1.0000001", "0.1", "1e+300"; "nan", "inf", "-inf").
std::string format_exact(double value);

// A number as printf("%.*g") writes it with `significant_digits` digits ("nan", never "-nan";
// "inf", "-inf"); 17 digits give back the same double.
std::string format_number(double value, int significant_digits = 6);

// Writes `text` on stdio's stderr and flushes it, waiting for any plot being drawn (which
// captures descriptor 2). Thread-safe; front ends write their warnings and errors through it. A
// write error shows in ferror(stderr).
void write_stderr(std::string_view text);

// `text` for a message: control bytes as \xNN (escape_control_characters), cut after about
// `shown` characters with "...".
std::string shorten_for_message(std::string_view text, std::size_t shown = 40);

// `text` with control characters (a newline, a terminal escape) written as \xNN.
std::string escape_control_characters(std::string_view text);

}  // namespace fss
