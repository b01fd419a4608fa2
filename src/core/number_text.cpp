#include "core/number_text.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace fss {

double parse_finite_number(std::string_view text) {
  if (!text.empty() && text[0] == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
      !std::isfinite(value)) {
    return std::nan("");
  }
  return value;
}

}  // namespace fss
