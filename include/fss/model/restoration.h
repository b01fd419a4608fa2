// The restorations fssim applies to the mirror-extended observed rows (docs/method.md §12): the
// paper's inverse filter (the default), Tikhonov and Wiener, and their stationary figures of
// merit for code design. Conventions: fss/fss.h.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace fss {

enum class RestorationMethod { kInverse, kWiener, kTikhonov };
std::string to_string(RestorationMethod method);
std::optional<RestorationMethod> restoration_method_from_string(std::string_view text);

// The signal prior of the Wiener filter: kOracle takes the power spectrum of the ground truth (it
// sees the image), kPowerLaw S(xi) = c |xi|^-gamma.
enum class PriorKind { kOracle, kPowerLaw };

// Bounds of the Tikhonov regularization and of the power-law prior.
inline constexpr double kMinRegularization = 1e-8;  // also the range of "optimal"
inline constexpr double kMaxRegularization = 1e2;
inline constexpr double kMaxPriorExponent = 8.0;

struct RestorationOptions {
  RestorationMethod method = RestorationMethod::kInverse;
  // Tikhonov's lambda, dimensionless: H = conj(K) / (|K|^2 + lambda kappa^2), kappa = dt sum
  // |alpha_k|. Empty: the lambda in [kMinRegularization, kMaxRegularization] minimising the
  // exact expected error of the run (simulations, an oracle) or the stationary figure (design).
  std::optional<double> regularization;
  // Wiener's prior.
  PriorKind prior = PriorKind::kPowerLaw;
  double prior_exponent = 2.0;  // gamma, in [0, kMaxPriorExponent]
  // c, the level of a power-law prior in gray levels^2 at level 100 (design only; a simulation
  // estimates it from a calibration observation). Empty: kDefaultPriorLevel in design.
  std::optional<double> prior_level;

  // False with a message naming the field when a value is out of range or set for a method that
  // does not use it (lambda without Tikhonov, a prior without Wiener).
  bool IsValid(std::string* error) const;
};

// The power-law prior's default level c in design (docs/method.md §12).
inline constexpr double kDefaultPriorLevel = 180.0;

// "inverse", "tikhonov (lambda 0.001)", "tikhonov (lambda optimal)", "wiener (power-law prior,
// gamma 2)", "wiener (oracle prior)".
std::string describe(const RestorationOptions& options);

// Parses a prior: "oracle", "power-law", "power-law:GAMMA" or "power-law:GAMMA:C" into
// `options` (prior, prior_exponent, prior_level); false with a message otherwise.
bool parse_prior(std::string_view text, RestorationOptions* options, std::string* error);
// The prior's text as parse_prior reads it ("oracle", "power-law:2", "power-law:2:180").
std::string prior_text(const RestorationOptions& options);

}  // namespace fss
