#include "fss/model/restoration.h"

#include <cmath>
#include <string>

#include "core/enum_names.h"
#include "core/number_text.h"
#include "fss/core/error.h"

namespace fss {

namespace {
constexpr detail::EnumNames<RestorationMethod, 3> kMethodNames{
    {{RestorationMethod::kInverse, "inverse"},
     {RestorationMethod::kWiener, "wiener"},
     {RestorationMethod::kTikhonov, "tikhonov"}}};

// "" when `lambda` is a usable Tikhonov regularization.
std::string regularization_rule(double lambda) {
  if (!(std::isfinite(lambda) && lambda >= kMinRegularization && lambda <= kMaxRegularization)) {
    return "must lie in [" + format_exact(kMinRegularization) + ", " +
           format_exact(kMaxRegularization) + "]";
  }
  return "";
}

std::string exponent_rule(double gamma) {
  if (!(std::isfinite(gamma) && gamma >= 0.0 && gamma <= kMaxPriorExponent)) {
    return "must lie in [0, " + format_exact(kMaxPriorExponent) + "]";
  }
  return "";
}

std::string level_rule(double c) {
  if (!(std::isfinite(c) && c >= 1e-100 && c <= 1e100)) return "must lie in [1e-100, 1e100]";
  return "";
}
}  // namespace

std::string to_string(RestorationMethod method) { return detail::enum_name(kMethodNames, method); }

std::optional<RestorationMethod> restoration_method_from_string(std::string_view text) {
  return detail::enum_from_name(kMethodNames, text);
}

bool RestorationOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (regularization) {
    if (method != RestorationMethod::kTikhonov) {
      return fail("regularization = " + format_exact(*regularization) +
                  ": only the tikhonov restoration takes a regularization, this one is " +
                  to_string(method));
    }
    if (const std::string rule = regularization_rule(*regularization); !rule.empty()) {
      return fail("regularization = " + format_exact(*regularization) + ": " + rule);
    }
  }
  const bool default_prior = prior == PriorKind::kPowerLaw && prior_exponent == 2.0 && !prior_level;
  if (!default_prior && method != RestorationMethod::kWiener) {
    return fail("prior = " + prior_text(*this) +
                ": only the wiener restoration takes a prior, this one is " + to_string(method));
  }
  if (const std::string rule = exponent_rule(prior_exponent); !rule.empty()) {
    return fail("prior_exponent = " + format_exact(prior_exponent) + ": " + rule);
  }
  if (prior_level) {
    if (prior == PriorKind::kOracle) {
      return fail("prior_level = " + format_exact(*prior_level) +
                  ": the oracle prior has no level (it is the image's own spectrum)");
    }
    if (const std::string rule = level_rule(*prior_level); !rule.empty()) {
      return fail("prior_level = " + format_exact(*prior_level) + ": " + rule);
    }
  }
  return true;
}

std::string prior_text(const RestorationOptions& options) {
  if (options.prior == PriorKind::kOracle) return "oracle";
  std::string text = "power-law:" + format_exact(options.prior_exponent);
  if (options.prior_level) text += ":" + format_exact(*options.prior_level);
  return text;
}

std::string describe(const RestorationOptions& options) {
  switch (options.method) {
    case RestorationMethod::kInverse:
      return "inverse";
    case RestorationMethod::kTikhonov:
      return "tikhonov (lambda " +
             (options.regularization ? format_exact(*options.regularization) : "optimal") + ")";
    case RestorationMethod::kWiener:
      if (options.prior == PriorKind::kOracle) return "wiener (oracle prior)";
      return "wiener (power-law prior, gamma " + format_exact(options.prior_exponent) +
             (options.prior_level ? ", level " + format_exact(*options.prior_level) : "") + ")";
  }
  return "inverse";
}

bool parse_prior(std::string_view text, RestorationOptions* options, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) {
      *error = "prior '" + shorten_for_message(text) + "': " + why +
               " (expected oracle, power-law or power-law:GAMMA; code design also takes "
               "power-law:GAMMA:C)";
    }
    return false;
  };
  if (text == "oracle") {
    options->prior = PriorKind::kOracle;
    options->prior_exponent = 2.0;
    options->prior_level.reset();
    return true;
  }
  constexpr std::string_view kPowerLaw = "power-law";
  if (text.substr(0, kPowerLaw.size()) != kPowerLaw) return fail("unknown prior");
  std::string_view rest = text.substr(kPowerLaw.size());
  double gamma = 2.0;
  std::optional<double> level;
  if (!rest.empty()) {
    if (rest.front() != ':') return fail("unknown prior");
    rest.remove_prefix(1);
    const std::size_t colon = rest.find(':');
    gamma = parse_finite_number(rest.substr(0, colon));
    if (std::isnan(gamma)) return fail("GAMMA is not a finite number");
    if (const std::string rule = exponent_rule(gamma); !rule.empty()) return fail("GAMMA " + rule);
    if (colon != std::string_view::npos) {
      const double c = parse_finite_number(rest.substr(colon + 1));
      if (std::isnan(c)) return fail("C is not a finite number");
      if (const std::string rule = level_rule(c); !rule.empty()) return fail("C " + rule);
      level = c;
    }
  }
  options->prior = PriorKind::kPowerLaw;
  options->prior_exponent = gamma + 0.0;  // -0 is 0
  options->prior_level = level;
  return true;
}

}  // namespace fss
