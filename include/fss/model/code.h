// Flutter shutter codes: the gains alpha_0 .. alpha_{L-1}, their text format
// and the six codes of the paper, which are embedded in the library.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fss {

// How the code is applied (docs/method.md §2): analog gains in [0, 1] modulate the light
// of one exposure; numerical gains (any real) weight a burst of L frames.
enum class ShutterMode { kNumerical, kAnalog };
std::string to_string(ShutterMode mode);
std::optional<ShutterMode> shutter_mode_from_string(std::string_view text);

struct ShutterCode {
  std::string name;           // built-in name, or the file it was read from
  std::vector<double> gains;  // alpha_k, k = 0 .. L-1
  int length() const { return static_cast<int>(gains.size()); }
};

// Parses the code text format: numbers separated by white space, commas or semicolons, '#'
// starting a comment to the end of the line (the reference program's code.txt reads as is).
// Throws a runtime fss::Error naming `origin`, the line and the token for an empty text, a
// non-numeric token, a NaN, infinite or out-of-range value, or more than kMaxCodeLength gains.
ShutterCode parse_code_text(std::string_view text, const std::string& origin);

// Names of the built-in codes: snapshot, accumulation, raskar, random, mip, sinc.
std::vector<std::string> builtin_code_names();
std::optional<ShutterCode> builtin_code(std::string_view name);

// Longest code fssim works with: parse_code_text, check_code_for_mode, generate and optimize
// refuse a longer one before any work.
inline constexpr int kMaxCodeLength = 1024;

// Largest code file load_code reads (a code of any usable length is far smaller).
inline constexpr std::size_t kMaxCodeFileBytes = std::size_t{16} << 20;

// A built-in name, or else the path of a code file. Throws a usage fss::Error, naming it as
// `named_as` ("--code", "code"), when it is neither; a runtime one when the file cannot be read,
// is larger than kMaxCodeFileBytes or does not parse.
ShutterCode load_code(const std::string& name_or_path, const std::string& named_as = "code");

// The reference program's code.txt format: one gain per line followed by ';'.
std::string format_code_txt(const ShutterCode& code);

// sum alpha_k, sum alpha_k^2, max |alpha_k|, and ||alpha||_1 / sup |alpha| (0 for an all-zero
// code).
double gain_sum(const std::vector<double>& gains);
double gain_square_sum(const std::vector<double>& gains);
double gain_max_abs(const std::vector<double>& gains);
double normalized_l1(const std::vector<double>& gains);

namespace detail {
struct EmbeddedCode {
  const char* name;
  const char* text;
};
const std::vector<EmbeddedCode>& embedded_codes();
}  // namespace detail

}  // namespace fss
