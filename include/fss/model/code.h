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

// Parses the code text format: numbers separated by white space, commas or
// semicolons; '#' starts a comment running to the end of the line. The paper
// program's code.txt ("1;" per line) is accepted as is. Throws a runtime
// fss::Error naming `origin`, the line and the token when the text is empty,
// holds a non-numeric token, or a NaN, infinite or out-of-range value. Tokens
// are quoted in messages cut to about 40 characters, control bytes written as \xNN.
ShutterCode parse_code_text(std::string_view text, const std::string& origin);

// Names of the built-in codes: snapshot, accumulation, raskar, random, mip, sinc.
std::vector<std::string> builtin_code_names();
std::optional<ShutterCode> builtin_code(std::string_view name);

// Longest code fssim works with. The analysis of a code (its |K| scanned on
// 64 L points of [0, pi], each a sum over the L gains) costs O(L^2): 1024
// gains take about half a second, and a longer code is refused before any
// work (parse_code_text, check_code_for_mode, generate and optimize).
inline constexpr int kMaxCodeLength = 1024;

// Largest code file load_code reads (a code of any usable length is far smaller).
inline constexpr std::size_t kMaxCodeFileBytes = std::size_t{16} << 20;

// A built-in name, or else the path of a code file. Throws a usage fss::Error
// when it is neither (naming it as `named_as`: "--code 'x' is neither ...",
// or "code 'x'" for a positional argument), a runtime one when the file
// cannot be read, is larger than kMaxCodeFileBytes or does not parse.
ShutterCode load_code(const std::string& name_or_path, const std::string& named_as = "code");

// The reference program's code.txt format: one gain per line followed by ';'.
std::string format_code_txt(const ShutterCode& code);

// Sums used by the theory: sum alpha_k, sum alpha_k^2, max |alpha_k|, and
// the normalized L1 norm ||alpha||_1 / sup |alpha| (0 for an all-zero code).
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
