// libFuzzer target: fss::parse_campaign_file on arbitrary text, then
// CampaignSpec::IsValid and the value lists of a spec it accepts. A usage
// fss::Error of one short line is the expected end for bad text; any other
// exception, a crash, a sanitizer report, a long or multi-line message, a
// non-finite value or a list longer than kMaxCampaignValues is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fss/campaign/spec.h"
#include "fuzz_check.h"

namespace {

void check_list(const std::string& text, const std::string& field) {
  const fss::ValueList list = fss::parse_value_list(text, field);
  if (list.values.empty() || list.values.size() > fss::kMaxCampaignValues) __builtin_trap();
  for (const double v : list.values) {
    if (!std::isfinite(v)) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  constexpr std::size_t kMaxMessage = 400;
  try {
    const fss::CampaignSpec spec = fss::parse_campaign_file(text, "fuzz.json");
    std::string error;
    if (!spec.IsValid(&error)) {
      if (error.empty() || error.size() > kMaxMessage) __builtin_trap();
      for (const char c : error) {
        if (static_cast<unsigned char>(c) < 0x20) __builtin_trap();
      }
      return 0;
    }
    check_list(spec.velocity, "velocity");
    if (!spec.restore_velocity.empty()) check_list(spec.restore_velocity, "restore_velocity");
    check_list(spec.snr, "snr");
    check_list(spec.dt, "dt");
  } catch (const fss::Error& e) {
    fss::fuzz::check_message(e, kMaxMessage);
  }
  return 0;
}
