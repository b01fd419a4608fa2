// Private to the campaign tables (table.cpp): numbers rounded as a table of
// results prints them, as a mantissa and a power of ten.
#pragma once

#include <optional>
#include <string>

namespace fss::table_numbers {

// A rounded number, mantissa × 10^exponent; mantissa "inf" or "-inf" for an
// infinite value (exponent 0).
struct Rounded {
  std::string mantissa;  // "2.3540", "-0.75", "1.2346"
  int exponent = 0;      // 0 unless the number is large or small (scientific form)
};

// A mean and its standard error sharing one exponent.
struct MeanSe {
  Rounded mean;
  Rounded se;
};

// The standard error `se` (> 0, finite) to `digits` significant digits and
// `mean` (finite) to the same decimal place; scientific when the larger of
// |mean| and se is at least 1e6 or below 1e-3.
MeanSe round_mean_se(double mean, double se, int digits);

// The power of ten of the last digit round_mean_se keeps of a standard error
// `se` (> 0, finite) at `digits` significant digits: -4 for 0.0031 at 2.
int last_place(double se, int digits);

// `value` rounded to the decimal place 10^place, in the form round_mean_se
// gives a mean; infinite values as "inf", "-inf".
Rounded round_to_place(double value, int place);

// `value` to `digits` significant digits (an integer below 1e6 exactly);
// infinite values as "inf", "-inf".
Rounded round_significant(double value, int digits);

// The number a results cell holds: finite or infinite ("inf", "-inf");
// nullopt for an empty cell, NaN or text that is not a number.
std::optional<double> parse_number(const std::string& text);

}  // namespace fss::table_numbers
