#include "campaign/table_numbers.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace fss::table_numbers {

namespace {

// Numbers are written mantissa × 10^exponent from this decade up, and below
// the other.
constexpr int kLargeDecade = 6;
constexpr int kSmallDecade = -3;
// No place or exponent below this one, so that 10^place stays a normal double
// (subnormal values print as 0 there).
constexpr int kSmallestPlace = -300;

// The decade of |value| (> 0): floor(log10 |value|).
int decade(double value) { return static_cast<int>(std::floor(std::log10(std::abs(value)))); }

// The exponent a number of magnitude `magnitude` is written with: 0 between
// 1e-3 and 1e6, its decade outside.
int form_exponent(double magnitude) {
  if (!(magnitude > 0.0)) return 0;
  const int d = std::max(decade(magnitude), kSmallestPlace);
  return d >= kLargeDecade || d < kSmallDecade ? d : 0;
}

Rounded infinite(double value) { return {value > 0.0 ? "inf" : "-inf", 0}; }

// `value` rounded to the place 10^place and written over 10^exponent:
// value / 10^exponent with exponent - place decimals; "-0.00" is "0.00".
Rounded render(double value, int place, int exponent) {
  const int decimals = exponent - place;
  double shown = value / std::pow(10.0, exponent);
  if (decimals < 0) {
    shown = std::round(value / std::pow(10.0, place)) * std::pow(10.0, place - exponent);
  }
  const int precision = std::max(0, decimals);
  std::string text(static_cast<std::size_t>(std::snprintf(nullptr, 0, "%.*f", precision, shown)),
                   '\0');
  std::snprintf(text.data(), text.size() + 1, "%.*f", precision, shown);
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return {text, exponent};
}

}  // namespace

// The place of the SE's last digit: decade(se) - digits + 1, one higher when
// the SE rounds up to 10^digits units there (0.0995 at 2 digits is 0.10).
int last_place(double se, int digits) {
  int place = std::max(decade(se) - (digits - 1), kSmallestPlace);
  if (std::round(se / std::pow(10.0, place)) >= std::pow(10.0, digits)) ++place;
  return place;
}

MeanSe round_mean_se(double mean, double se, int digits) {
  const int place = last_place(se, digits);
  const int exponent = form_exponent(std::max(std::abs(mean), se));
  return {render(mean, place, exponent), render(se, place, exponent)};
}

Rounded round_to_place(double value, int place) {
  if (std::isinf(value)) return infinite(value);
  return render(value, place, form_exponent(std::max(std::abs(value), std::pow(10.0, place))));
}

Rounded round_significant(double value, int digits) {
  if (std::isinf(value)) return infinite(value);
  if (value == std::round(value) && std::abs(value) < 1e6) return render(value, 0, 0);
  const int place = std::max(decade(value) - (digits - 1), kSmallestPlace);
  Rounded rounded = render(value, place, form_exponent(std::abs(value)));
  // 9.9996e6 at 4 digits is 1.000e7, not 10.00e6.
  if (rounded.exponent != 0 && std::abs(std::stod(rounded.mantissa)) >= 10.0) {
    rounded = render(value, place + 1, rounded.exponent + 1);
  }
  return rounded;
}

std::optional<double> parse_number(const std::string& text) {
  if (text == "inf") return HUGE_VAL;
  if (text == "-inf") return -HUGE_VAL;
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

}  // namespace fss::table_numbers
