// Checks shared by the options of the design modules (GenerateOptions,
// OptimizeOptions); not part of the public interface.
#pragma once

#include <cmath>
#include <string>

#include "fss/core/error.h"

namespace fss::design_detail {

// For IsValid: sets *error (when not null) to `message` and returns false.
inline bool invalid(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

// Whether a code length lies in [1, max_length] and the slot length dt is
// finite and > 0. If not, *error (when not null) names the first field at
// fault, its value and the rule: "length = 0: must lie in [1, 4096]".
inline bool code_length_and_dt_are_valid(int length, int max_length, double dt,
                                         std::string* error) {
  if (length < 1 || length > max_length) {
    return invalid(error, "length = " + std::to_string(length) + ": must lie in [1, " +
                              std::to_string(max_length) + "]");
  }
  if (!(std::isfinite(dt) && dt > 0.0)) {
    return invalid(error, "dt = " + format_exact(dt) + ": must be finite and > 0");
  }
  return true;
}

}  // namespace fss::design_detail
