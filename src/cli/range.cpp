#include "range.h"

#include <cmath>
#include <string_view>

#include "core/number_text.h"
#include "fss/core/error.h"

namespace fssim {

std::vector<double> parse_range(const std::string& text, const std::string& option) {
  const std::string where = option + " '" + fss::shorten_for_message(text) + "'";
  const auto first = text.find(':');
  if (first == std::string::npos) {
    const double value = fss::parse_finite_number(text);
    if (std::isnan(value)) {
      fss::throw_usage_error(where + ": expected a finite number or start:stop:step");
    }
    return {value};
  }
  const auto second = text.find(':', first + 1);
  if (second == std::string::npos || text.find(':', second + 1) != std::string::npos) {
    fss::throw_usage_error(where + ": a range has three parts, start:stop:step");
  }
  const std::string_view view(text);
  const double start = fss::parse_finite_number(view.substr(0, first));
  const double stop = fss::parse_finite_number(view.substr(first + 1, second - first - 1));
  const double step = fss::parse_finite_number(view.substr(second + 1));
  if (std::isnan(start) || std::isnan(stop) || std::isnan(step)) {
    fss::throw_usage_error(where + ": start, stop and step must be finite numbers");
  }
  if (!(step > 0.0)) fss::throw_usage_error(where + ": step must be > 0");
  if (stop < start) fss::throw_usage_error(where + ": stop must not be below start");
  // A value within half a step of stop counts (rounding never drops stop).
  const double count = std::floor((stop - start) / step + 0.5) + 1.0;
  if (!(count <= kMaxRangePoints)) {
    fss::throw_usage_error(where + ": more than " + std::to_string(kMaxRangePoints) +
                           " values; use a larger step");
  }
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < static_cast<int>(count); ++i) {
    values.push_back(start + i * step);
    if (!std::isfinite(values.back())) {
      fss::throw_usage_error(where + ": its values leave the range of doubles");
    }
  }
  return values;
}

}  // namespace fssim
