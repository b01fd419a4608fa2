// Value ranges on the command line: "V" or "start:stop:step".
#pragma once

#include <string>
#include <vector>

namespace fssim {

// Most values a range may hold.
inline constexpr int kMaxRangePoints = 10000;

// Parses `text`, the value of command-line option `option` (named in errors):
// a single finite number V, or start:stop:step meaning start, start + step,
// ..., up to the last value not beyond stop + step / 2 (so an inclusive stop
// survives rounding). Values are start + i step, not accumulated sums.
// Throws a usage fss::Error naming the option when the text is not a finite
// number or range, step <= 0, stop < start, or the range holds more than
// kMaxRangePoints values.
std::vector<double> parse_range(const std::string& text, const std::string& option);

}  // namespace fssim
