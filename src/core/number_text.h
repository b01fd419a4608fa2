// Numbers written as text, as the command line and campaign files give them.
#pragma once

#include <string_view>

namespace fss {

// The finite number that fills all of `text` (a leading '+' allowed, as in
// "+0.5"), or NaN when `text` is empty, is not a number to its end, or reads
// as an infinity or NaN.
double parse_finite_number(std::string_view text);

}  // namespace fss
