// libFuzzer target: `campaign check` on arbitrary results and expectations
// (fss::CheckCampaignResults, parse_csv, check_junit_xml). The first byte
// chooses the tolerances, the rest is RESULTS, then "\n--\n" and EXPECTED
// (without it, EXPECTED is RESULTS). A usage fss::Error of one short line is
// the expected end for bad text; any other exception, a crash, a sanitizer
// report, a long or multi-line message (of an error or of a comparison), a
// "nan" in a message of files without one (a NaN difference or tolerance),
// or a report whose JUnit XML miscounts its failures is a bug. A quoted cell
// may spell "nan" only once its quotes are removed (`"a)na"n"` reads a)nan),
// so the input is searched for "nan" with every quote removed.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fss/campaign/check.h"
#include "fuzz_check.h"

namespace {

constexpr std::size_t kMaxMessage = 400;
constexpr std::size_t kMaxCaseMessage = 4096;

fss::CheckOptions options_of(std::uint8_t choice) {
  fss::CheckOptions options;
  // Each tolerance given or not (none: the default rules), or --exact.
  if (choice & 1) options.abs_tolerance = 0.01;
  if (choice & 2) options.rel_tolerance = 0.1;
  if (choice & 4) options.k_standard_errors = 3.0;
  if (choice & 8) options.columns = {"rmse_mean", "status"};
  options.exact = (choice & 16) != 0 && (choice & 3) == 0;
  return options;
}

// Whether `text` holds "nan" in any case (strtod reads every spelling).
bool has_nan(const std::string& text) {
  for (std::size_t i = 0; i + 3 <= text.size(); ++i) {
    if ((text[i] | 0x20) == 'n' && (text[i + 1] | 0x20) == 'a' && (text[i + 2] | 0x20) == 'n') {
      return true;
    }
  }
  return false;
}

// One short line; no NaN unless the files wrote one (a difference or a
// tolerance is never NaN).
void check_case(const fss::CheckCase& c, bool nan_in_input) {
  const std::string& m = c.message;
  if (m.empty() || m.size() > kMaxCaseMessage) __builtin_trap();
  for (const char ch : m) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte < 0x20 || byte == 0x7f) __builtin_trap();
  }
  if (!nan_in_input && has_nan(m)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::size_t separator = text.find("\n--\n");
  const std::string results = text.substr(0, separator);
  const std::string expected =
      separator == std::string::npos ? results : text.substr(separator + 4);
  try {
    const fss::CheckReport report =
        fss::CheckCampaignResults(results, "r.csv", expected, "e.csv", options_of(data[0]));
    std::string unquoted = text;
    std::erase(unquoted, '"');
    for (const fss::CheckCase& c : report.cases) check_case(c, has_nan(unquoted));
    const std::string xml = fss::check_junit_xml(report, "fuzz");
    const std::string failures = "failures=\"" + std::to_string(report.failures()) + "\"";
    if (xml.find(failures) == std::string::npos) __builtin_trap();
  } catch (const fss::Error& e) {
    if (e.kind() != fss::ErrorKind::kUsage) __builtin_trap();
    fss::fuzz::check_message(e, kMaxMessage);
  }
  return 0;
}
