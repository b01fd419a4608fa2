// libFuzzer target: fss::parse_code_text on arbitrary text. A runtime
// fss::Error is the expected end for bad text; any other exception escaping,
// a crash, a sanitizer report, a message of more than one short line, a
// non-finite gain, or a code whose reference-format text (code.txt) does not
// read back to the same gains is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fss/core/error.h"
#include "fss/model/code.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const fss::ShutterCode code = fss::parse_code_text(text, "fuzz.txt");
    if (code.gains.empty()) __builtin_trap();
    for (const double gain : code.gains) {
      if (!std::isfinite(gain)) __builtin_trap();
    }
    const fss::ShutterCode again = fss::parse_code_text(fss::format_code_txt(code), "again.txt");
    if (again.gains != code.gains) __builtin_trap();
  } catch (const fss::Error& error) {
    if (error.kind() != fss::ErrorKind::kRuntime) __builtin_trap();
    const std::string_view message = error.what();
    if (message.empty() || message.size() > 240) __builtin_trap();
    for (const char c : message) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte < 0x20 || byte == 0x7f) __builtin_trap();  // one line, no terminal escapes
    }
  }
  return 0;
}
