#include "pipeline/plan_core.h"

#include <algorithm>
#include <bit>
#include <complex>
#include <cstdint>
#include <limits>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "pipeline/noise_weights.h"
#include "pipeline/restoration_filter.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/run_checks.h"

namespace fss {

// The members every constructor sets the same way.
PlanCore::PlanCore(const SimulationOptions& options, const Geometry& geometry,
                   const ShutterCode& code)
    : code_name_(code.name),
      gains_(code.gains),
      mode_(options.mode),
      velocity_(options.velocity_px_per_slot),
      restore_velocity_(options.restore_velocity_px_per_slot.value_or(velocity_)),
      dt_(options.dt),
      margin_(options.rmse_margin_columns),
      noisy_(options.noise != NoiseModel::kNone),
      restoration_options_(options.restoration),
      geometry_(geometry),
      windows_(metric_windows(geometry_, margin_)) {}

PlanCore::PlanCore(const SimulationOptions& options, int width, const ShutterCode& code)
    : PlanCore(options, checked_geometry(options, width, code), code) {
  distribution_ = options.velocity_distribution;
  if (distribution_) {
    // K(0) = dt sum alpha_k at every velocity: the divisor of every trial's observed image.
    kernel_ = analyze_kernel(code.gains, restore_velocity_, dt_);
    set_observed_divisor(code);
    return;
  }
  observer_.emplace(width, code.gains, options.mode, observation_params(options, geometry_));
  analyze(code);
  plan_filter(code, true);
}

PlanCore::PlanCore(const SimulationOptions& options, const Geometry& geometry,
                   const ShutterCode& code, VelocityPart part)
    : PlanCore(options, geometry, code) {
  observer_.emplace(geometry.width, code.gains, options.mode,
                    observation_params(options, geometry_));
  if (part == VelocityPart::kTrial) {
    analyze(code);
  } else {
    kernel_.invertible = true;
  }
  plan_filter(code, part == VelocityPart::kPrediction);
}

void PlanCore::analyze(const ShutterCode& code) {
  // The kernel the restoration inverts, K at the restore velocity v_r
  // (docs/method.md §1), the divisor of the observed image, and their warnings.
  kernel_ = analyze_kernel(code.gains, restore_velocity_, dt_);
  if (!kernel_.invertible) {
    const bool inverse = restoration_options_.method == RestorationMethod::kInverse;
    warnings_.push_back(
        "code '" + escape_control_characters(code.name) + "' is not invertible at velocity " +
        format_exact(restore_velocity_) + ": min |K| = " + format_number(kernel_.min_abs) +
        " at xi = " + format_number(kernel_.min_abs_xi) +
        (inverse ? "; the restoration cannot recover the frequencies where K vanishes and "
                   "amplifies the noise near them: no finite error prediction exists"
                 : "; the " + to_string(restoration_options_.method) +
                       " restoration damps the frequencies where K vanishes: the restored image "
                       "loses them"));
  }
  set_observed_divisor(code);
}

void PlanCore::set_observed_divisor(const ShutterCode& code) {
  observed_divisor_ = kernel_.k0;
  if (transfer_vanishes(std::abs(kernel_.k0), transfer_scale(code.gains, dt_))) {
    observed_divisor_ = dt_ * gain_max_abs(code.gains);
    warnings_.push_back("K(0) = dt * sum of gains vanishes (it is " + format_number(kernel_.k0) +
                        "): observed.png is divided by dt * max |gain| = " +
                        format_number(observed_divisor_) + " instead");
  }
}

// The restorer, M and W(j) (docs/method.md §6, §6b, §12) of a filter that
// does not depend on the image: the inverse filter, or Tikhonov at a given
// lambda. Without `prediction_parts`, the restorer only.
void PlanCore::plan_filter(const ShutterCode& code, bool prediction_parts) {
  restoration_.options = restoration_options_;
  m_amplification_ = prediction_parts ? std::numeric_limits<double>::infinity() : 0.0;
  const int n = geometry_.mirror_width;
  switch (restoration_options_.method) {
    case RestorationMethod::kInverse:
      restorer_.emplace(geometry_, code.gains, restore_velocity_, dt_);
      if (!kernel_.invertible || !prediction_parts) return;
      m_amplification_ = mean_inverse_power(code.gains, restore_velocity_, dt_, n);
      if (noisy_) {
        noise_weights_ = noise_energy_weights(geometry_, code.gains, restore_velocity_, dt_,
                                              windows_.rmse_first, windows_.rmse_end);
      }
      return;
    case RestorationMethod::kTikhonov:
      if (!restoration_options_.regularization) return;  // the optimum depends on the image
      {
        const double lambda = *restoration_options_.regularization;
        FilterBins filter = tikhonov_filter_bins(code.gains, restore_velocity_, dt_, n, lambda);
        if (prediction_parts) m_amplification_ = filter_mean_power(filter.h, n);
        if (noisy_ && prediction_parts) {
          noise_weights_ = noise_energy_weights(geometry_, filter_impulse_response(filter.h, n),
                                                windows_.rmse_first, windows_.rmse_end);
        }
        restorer_.emplace(geometry_, std::move(filter));
        restoration_.regularization = lambda;
      }
      return;
    case RestorationMethod::kWiener:
      return;  // its prior depends on the image
  }
}

namespace {

bool same_restoration(const RestorationOptions& a, const RestorationOptions& b) {
  return a.method == b.method && a.regularization == b.regularization && a.prior == b.prior &&
         a.prior_exponent == b.prior_exponent && a.prior_level == b.prior_level;
}

// Compared as bits: -0.0 and 0.0 are different velocities to the filters.
bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same_distribution(const std::optional<VelocityDistribution>& a,
                       const std::optional<VelocityDistribution>& b) {
  if (!a || !b) return !a && !b;
  const auto same_point = [](const VelocityPoint& p, const VelocityPoint& q) {
    return same_bits(p.velocity, q.velocity) && same_bits(p.weight, q.weight);
  };
  return a->kind == b->kind && same_bits(a->low, b->low) && same_bits(a->high, b->high) &&
         same_bits(a->mean, b->mean) && same_bits(a->sd, b->sd) &&
         a->bounds_given == b->bounds_given && a->points.size() == b->points.size() &&
         std::equal(a->points.begin(), a->points.end(), b->points.begin(), same_point);
}

}  // namespace

bool PlanCore::fits(const SimulationOptions& options, int width, const ShutterCode& code) const {
  const double v = options.velocity_px_per_slot;
  const auto same = same_bits;
  // Under a distribution the plan holds no part that depends on the noise.
  const bool noise_fits =
      distribution_ || options.noise == NoiseModel::kNone || noisy_ || !kernel_.invertible;
  return same_distribution(options.velocity_distribution, distribution_) &&
         code.name == code_name_ && code.gains.size() == gains_.size() &&
         std::equal(gains_.begin(), gains_.end(), code.gains.begin(), same) &&
         options.mode == mode_ && same(v, velocity_) &&
         same(options.restore_velocity_px_per_slot.value_or(v), restore_velocity_) &&
         same(options.dt, dt_) && width == geometry_.width &&
         options.rmse_margin_columns == margin_ &&
         same_restoration(options.restoration, restoration_options_) && noise_fits;
}

std::size_t PlanCore::bytes() const {
  const std::size_t bins = static_cast<std::size_t>(geometry_.width) / 2 + 1;
  const std::size_t filters =
      observer_ ? (mode_ == ShutterMode::kAnalog ? 1 : gains_.size()) * bins : 0;
  return sizeof(*this) + sizeof(std::complex<double>) * filters +
         (restorer_ ? restorer_->bytes() : 0) +
         sizeof(double) * (noise_weights_.size() + gains_.size());
}

}  // namespace fss
