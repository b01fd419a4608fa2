// fss error reporting: every failure is an fss::Error carrying a one-line,
// self-contained message that names the file, option or value at fault and
// what was expected. The kind tells a front end how to exit.
#pragma once

#include <stdexcept>
#include <string>

namespace fss {

enum class ErrorKind {
  kUsage,    // a parameter or a combination of parameters is not acceptable
  kRuntime,  // a file could not be read or written, or its content is bad
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

}  // namespace fss
