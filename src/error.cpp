#include "fss/error.h"

namespace fss {

Error::Error(ErrorKind kind, const std::string& message)
    : std::runtime_error(message), kind_(kind) {}

void throw_usage_error(const std::string& message) { throw Error(ErrorKind::kUsage, message); }

void throw_runtime_error(const std::string& message) { throw Error(ErrorKind::kRuntime, message); }

}  // namespace fss
