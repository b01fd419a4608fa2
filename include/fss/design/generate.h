// Generating flutter shutter codes: the paper's constructions (sinc, MIP) for
// a velocity and slot, random codes, the snapshot and the accumulation
// (docs/method.md §7). Conventions: core/image.h.
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

// True when the sinc and MIP constructions are defined: 0 < |v| dt < 2 (the
// band |theta| <= pi |v| dt is not empty and 1 / sinc_h stays finite on it).
bool design_band_is_valid(double velocity, double dt);

// The sinc code: gain k is the real part of the Fourier coefficient
//   (1 / 2 pi) int_{|theta| <= pi |v| dt} exp(i theta (k - c)) / sinc_h(theta) d theta,
// c = floor(L / 2), normalized so that max |alpha_k| = 1. Its |K| is flat on
// the band (up to the truncation to L gains). Throws a usage fss::Error unless
// length >= 1 and design_band_is_valid(velocity, dt).
std::vector<double> generate_sinc_code(int length, double velocity, double dt);

// The motion-invariant (MIP) code: target T(theta) = sqrt(pi / |theta|)
// exp(-i pi / 4 sign theta), time origin t0 = c, so gain k is the real part of
//   (1 / 2 pi) int_{|theta| <= pi |v| dt} T(theta) exp(i theta (k - c + 1/2)) / sinc_h(theta),
// normalized so that max |alpha_k| = 1. The 1 / sqrt(theta) singularity is
// removed exactly by the substitution theta = u^2. Same errors as above.
std::vector<double> generate_mip_code(int length, double velocity, double dt);

// Independent uniform gains on [-1, 1) (numerical) or [0, 1) (analog) from a
// generator seeded with `seed`; the same seed gives the same code everywhere.
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
