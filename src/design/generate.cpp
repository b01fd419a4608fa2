#include "fss/design/generate.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/enum_names.h"
#include "design/numerics.h"
#include "design/option_checks.h"
#include "fss/core/error.h"

namespace fss {

using design_detail::code_length_and_dt_are_valid;
using design_detail::invalid;
using design_detail::inverse_sinc_h;
using design_detail::simpson;

namespace {

// Sub-intervals of the generation integrals: the integrands oscillate at most
// L / 2 times over the band; 16384 Simpson steps put their error below 1e-9.
constexpr int kDesignIntegralIntervals = 16384;

constexpr detail::EnumNames<CodeFamily, 5> kCodeFamilyNames{
    {{CodeFamily::kSinc, "sinc"},
     {CodeFamily::kMip, "mip"},
     {CodeFamily::kRandom, "random"},
     {CodeFamily::kSnapshot, "snapshot"},
     {CodeFamily::kAccumulation, "accumulation"}}};

void check_design_arguments(const char* family, int length, double velocity, double dt) {
  if (length < 1) {
    throw_usage_error("the " + std::string(family) + " code needs a length >= 1, got " +
                      std::to_string(length));
  }
  if (!design_band_is_valid(velocity, dt)) {
    throw_usage_error("the " + std::string(family) + " code is designed on the band |theta| <= " +
                      "pi |v| dt, which needs 0 < |v| dt < 2; velocity " + format_exact(velocity) +
                      " and dt " + format_exact(dt) +
                      " give |v| dt = " + format_exact(std::abs(velocity) * dt));
  }
}

std::vector<double> normalized_to_unit_max(std::vector<double> gains) {
  const double sup = gain_max_abs(gains);
  if (sup > 0.0) {
    for (double& g : gains) g /= sup;
  }
  return gains;
}

// A code designed on the band |theta| <= pi |v| dt: gain k is
// coefficient(k - c, band) with c = L / 2 (integer division) and band =
// pi |v| dt, then the gains are scaled to max |gain| = 1.
template <typename Coefficient>
std::vector<double> band_limited_code(const char* family, int length, double velocity, double dt,
                                      const Coefficient& coefficient) {
  check_design_arguments(family, length, velocity, dt);
  const double band = M_PI * std::abs(velocity) * dt;
  const int c = length / 2;
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (int k = 0; k < length; ++k) gains[k] = coefficient(k - c, band);
  return normalized_to_unit_max(std::move(gains));
}

}  // namespace

std::string to_string(CodeFamily family) { return detail::enum_name(kCodeFamilyNames, family); }

std::optional<CodeFamily> code_family_from_string(std::string_view text) {
  return detail::enum_from_name(kCodeFamilyNames, text);
}

// The band |theta| <= pi |v| dt is then not empty and 1 / sinc_h stays finite on it.
bool design_band_is_valid(double velocity, double dt) {
  const double product = std::abs(velocity) * dt;
  return std::isfinite(product) && product > 0.0 && product < 2.0;
}

// Gain k is the real part of (1 / 2 pi) int_{|theta| <= pi |v| dt} exp(i theta (k - c)) /
// sinc_h(theta) d theta, c = floor(L / 2) (docs/method.md §7).
std::vector<double> generate_sinc_code(int length, double velocity, double dt) {
  return band_limited_code("sinc", length, velocity, dt, [](int offset, double band) {
    // T = 1, t0 = c + 1/2: the integrand exp(i theta (k - c)) / sinc_h(theta)
    // is even in its real part and odd in its imaginary part, so the
    // coefficient is (1 / pi) int_0^band cos(theta (k - c)) / sinc_h(theta).
    const double shift = offset;
    return simpson([&](double t) { return std::cos(t * shift) * inverse_sinc_h(t); }, 0.0, band,
                   kDesignIntegralIntervals) /
           M_PI;
  });
}

// Target T(theta) = sqrt(pi / |theta|) exp(-i pi / 4 sign theta), time origin t0 = c: gain k is
// the real part of (1 / 2 pi) int_{|theta| <= pi |v| dt} T(theta) exp(i theta (k - c + 1/2)) /
// sinc_h(theta) d theta (docs/method.md §7).
std::vector<double> generate_mip_code(int length, double velocity, double dt) {
  return band_limited_code("mip", length, velocity, dt, [](int offset, double band) {
    // T(theta) exp(i theta m) with m = k - c + 1/2: the values at theta and
    // -theta are complex conjugates, so the real part of the coefficient is
    // (1 / pi) int_0^band sqrt(pi / theta) cos(theta m - pi / 4) / sinc_h(theta).
    // With theta = u^2 (d theta = 2 u du) the singularity cancels:
    // (2 sqrt(pi) / pi) int_0^sqrt(band) cos(u^2 m - pi / 4) / sinc_h(u^2) du.
    const double m = offset + 0.5;
    const double integral = simpson(
        [&](double u) {
          const double theta = u * u;
          return std::cos(theta * m - M_PI / 4.0) * inverse_sinc_h(theta);
        },
        0.0, std::sqrt(band), kDesignIntegralIntervals);
    return 2.0 * std::sqrt(M_PI) * integral / M_PI;
  });
}

std::vector<double> generate_random_code(int length, std::uint64_t seed, bool analog) {
  if (length < 1) {
    throw_usage_error("the random code needs a length >= 1, got " + std::to_string(length));
  }
  std::mt19937_64 rng(seed);
  std::vector<double> gains(static_cast<std::size_t>(length));
  for (double& g : gains) {
    const double u = design_detail::uniform01(rng);
    g = analog ? u : 2.0 * u - 1.0;
  }
  return gains;
}

std::vector<double> snapshot_code(int length) {
  std::vector<double> gains(static_cast<std::size_t>(std::max(length, 0)), 0.0);
  if (!gains.empty()) gains[0] = 1.0;
  return gains;
}

std::vector<double> accumulation_code(int length) {
  return std::vector<double>(static_cast<std::size_t>(std::max(length, 0)), 1.0);
}

bool GenerateOptions::IsValid(std::string* error) const {
  if (!code_length_and_dt_are_valid(length, kMaxGeneratedCodeLength, dt, error)) return false;
  const auto fail = [error](const std::string& message) { return invalid(error, message); };
  if (!std::isfinite(velocity_px_per_slot)) {
    return fail("velocity_px_per_slot = " + format_exact(velocity_px_per_slot) +
                ": must be a finite number");
  }
  if ((family == CodeFamily::kSinc || family == CodeFamily::kMip) &&
      !design_band_is_valid(velocity_px_per_slot, dt)) {
    return fail("velocity_px_per_slot = " + format_exact(velocity_px_per_slot) +
                " with dt = " + format_exact(dt) + ": the " + to_string(family) +
                " code needs 0 < |velocity| dt < 2 (its design band is |theta| <= pi |v| dt)");
  }
  return true;
}

ShutterCode generate_code(const GenerateOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  ShutterCode code;
  code.name = to_string(options.family) + "-L" + std::to_string(options.length);
  switch (options.family) {
    case CodeFamily::kSinc:
      code.gains = generate_sinc_code(options.length, options.velocity_px_per_slot, options.dt);
      break;
    case CodeFamily::kMip:
      code.gains = generate_mip_code(options.length, options.velocity_px_per_slot, options.dt);
      break;
    case CodeFamily::kRandom:
      code.gains = generate_random_code(options.length, options.seed, options.analog);
      break;
    case CodeFamily::kSnapshot:
      code.gains = snapshot_code(options.length);
      break;
    case CodeFamily::kAccumulation:
      code.gains = accumulation_code(options.length);
      break;
  }
  return code;
}

}  // namespace fss
