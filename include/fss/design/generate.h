// Generating flutter shutter codes: the paper's constructions (sinc, MIP) for a velocity and
// slot, random codes, the snapshot and the accumulation (docs/method.md §7).
// Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fss/model/code.h"

namespace fss {

// Longest code generate_code accepts: the longest fssim analyses.
inline constexpr int kMaxGeneratedCodeLength = kMaxCodeLength;

enum class CodeFamily { kSinc, kMip, kRandom, kSnapshot, kAccumulation };
std::string to_string(CodeFamily family);
std::optional<CodeFamily> code_family_from_string(std::string_view text);

// True when the sinc and MIP constructions are defined: 0 < |v| dt < 2.
bool design_band_is_valid(double velocity, double dt);

// The sinc code (docs/method.md §7): |K| flat on the band |theta| <= pi |v| dt up to the
// truncation to L gains, max |alpha_k| = 1. Throws a usage fss::Error unless length >= 1 and
// design_band_is_valid(velocity, dt).
std::vector<double> generate_sinc_code(int length, double velocity, double dt);

// The motion-invariant (MIP) code (docs/method.md §7), max |alpha_k| = 1. Same errors as
// generate_sinc_code.
std::vector<double> generate_mip_code(int length, double velocity, double dt);

// Independent uniform gains on [-1, 1) (numerical) or [0, 1) (analog) from a generator seeded
// with `seed`: the same seed gives the same code everywhere. Throws a usage fss::Error for
// length < 1.
std::vector<double> generate_random_code(int length, std::uint64_t seed, bool analog);

std::vector<double> snapshot_code(int length);      // (1, 0, ..., 0)
std::vector<double> accumulation_code(int length);  // (1, ..., 1)

struct GenerateOptions {
  CodeFamily family = CodeFamily::kSinc;
  int length = 52;                    // 1 <= L <= kMaxGeneratedCodeLength
  double velocity_px_per_slot = 1.0;  // sinc and mip only: the band they are designed for
  double dt = 1.0;                    // > 0; sinc and mip only
  std::uint64_t seed = 0;             // random only
  bool analog = false;                // random only: gains in [0, 1) instead of [-1, 1)

  // False, with a message naming the field, its value and the rule.
  bool IsValid(std::string* error) const;
};

// The code of `options.family`, named "<family>-L<length>". Throws a usage
// fss::Error when the options are not valid.
ShutterCode generate_code(const GenerateOptions& options);

}  // namespace fss
