// libFuzzer target: the range syntaxes. The first byte chooses the parser:
// even, the campaign's value lists fss::parse_value_list ("a,b,c",
// "start:stop:step", "start:stop:xFACTOR"); odd, the command line's
// fssim::parse_range ("V" or "start:stop:step", sweep's --velocity, --snr).
// A usage fss::Error of one short line is the expected end for bad text; any
// other exception, a crash, a sanitizer report, a long or multi-line message,
// a non-finite value, more values than the bound, or a range whose values
// are not increasing is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fss/campaign/spec.h"
#include "fuzz_check.h"
#include "range.h"

namespace {

void check_values(const std::vector<double>& values, std::size_t max_count, bool increasing) {
  if (values.empty() || values.size() > max_count) __builtin_trap();
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) __builtin_trap();
    if (increasing && i > 0 && !(values[i] >= values[i - 1])) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool command_line = (data[0] & 1) != 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (command_line) {
      const std::vector<double> values = fssim::parse_range(text, "--velocity");
      check_values(values, fssim::kMaxRangePoints, true);
    } else {
      const fss::ValueList list = fss::parse_value_list(text, "velocity");
      // A list of items is in the order written; each range item increases.
      check_values(list.values, fss::kMaxCampaignValues, text.find(',') == std::string::npos);
    }
  } catch (const fss::Error& e) {
    fss::fuzz::check_message(e, 300);
  }
  return 0;
}
