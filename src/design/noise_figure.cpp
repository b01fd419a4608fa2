// The optimizer's objective Q M on a band grid (design/optimize.h).
#include <cmath>

#include "design/local_search.h"
#include "fss/core/error.h"
#include "fss/design/optimize.h"
#include "fss/model/kernel.h"
#include "fss/model/transfer.h"

namespace fss {

using design_detail::kInfinity;

void design_detail::make_band_basis(int length, double velocity, double dt, int grid,
                                    std::vector<double>* re, std::vector<double>* im) {
  re->assign(static_cast<std::size_t>(length) * grid, 0.0);
  im->assign(static_cast<std::size_t>(length) * grid, 0.0);
  for (int j = 0; j < grid; ++j) {
    const double xi = (j + 0.5) * M_PI / grid;
    const double theta = xi * velocity * dt;
    const double amplitude = dt * sinc_h(theta);
    for (int k = 0; k < length; ++k) {
      const double phase = -theta * (k + 0.5);
      (*re)[static_cast<std::size_t>(k) * grid + j] = amplitude * std::cos(phase);
      (*im)[static_cast<std::size_t>(k) * grid + j] = amplitude * std::sin(phase);
    }
  }
}

NoiseFigure::NoiseFigure(int length, double velocity, double dt, ShutterMode mode, int grid_points,
                         double readout_slots)
    : length_(length), grid_(grid_points), dt_(dt), readout_slots_(readout_slots), mode_(mode) {
  if (!(std::isfinite(readout_slots) && readout_slots >= 0.0)) {
    throw_usage_error("the readout noise of the noise figure, " + format_number(readout_slots) +
                      " slots of level-100 light, must be finite and >= 0 (a sensor too noisy "
                      "for the snr)");
  }
  if (length < 1) {
    throw_usage_error("the noise figure needs a code of at least 1 gain, got " +
                      std::to_string(length));
  }
  if (grid_points < 1) {
    throw_usage_error("the noise figure needs a band grid of at least 1 node, got " +
                      std::to_string(grid_points));
  }
  design_detail::make_band_basis(length, velocity, dt, grid_points, &basis_re_, &basis_im_);
}

// K is linear in alpha, K(xi_j) = sum_k alpha_k E_jk with
// E_jk = dt sinc_h(theta_j) exp(-i theta_j (k + 1/2)), so, G the grid's nodes,
//   dM / d alpha_k = -(2 / G) sum_j Re(conj(K_j) E_jk) / |K_j|^4,
//   dQ_eff / d alpha_k = 2 (dt + c) alpha_k (numerical) or dt (analog).
double NoiseFigure::Evaluate(std::span<const double> gains, std::span<double> gradient) const {
  if (static_cast<int>(gains.size()) != length_ ||
      (!gradient.empty() && static_cast<int>(gradient.size()) != length_)) {
    throw_usage_error("NoiseFigure::Evaluate: expected " + std::to_string(length_) + " gains");
  }
  // K_j = sum_k alpha_k E_jk.
  const std::size_t grid = static_cast<std::size_t>(grid_);
  std::vector<double> re(grid, 0.0), im(grid, 0.0);
  for (int k = 0; k < length_; ++k) {
    const double alpha = gains[k];
    if (alpha == 0.0) continue;
    const double* er = basis_re_.data() + k * grid;
    const double* ei = basis_im_.data() + k * grid;
    for (std::size_t j = 0; j < grid; ++j) {
      re[j] += alpha * er[j];
      im[j] += alpha * ei[j];
    }
  }
  // Q_eff = (dt + c) sum alpha^2 (numerical) or dt sum alpha + c (analog);
  // with c = 0 this is Q to the bit.
  const bool numerical = mode_ == ShutterMode::kNumerical;
  double q = 0.0;
  for (const double alpha : gains) q += numerical ? alpha * alpha : alpha;
  q = numerical ? q * (dt_ + readout_slots_) : q * dt_ + readout_slots_;
  if (!(q > 0.0)) return kInfinity;
  // |K_j| <= transfer_zero_level, compared as squares (no root per node)
  const double zero_level = transfer_zero_level(transfer_scale(gains, dt_));
  const double zero_power = zero_level * zero_level;

  // M = mean of 1 / |K_j|^2; K_j becomes K_j / |K_j|^4 for the gradient.
  double sum = 0.0;
  for (std::size_t j = 0; j < grid; ++j) {
    const double power = re[j] * re[j] + im[j] * im[j];
    if (!(power > zero_power)) return kInfinity;
    const double inverse = 1.0 / power;
    sum += inverse;
    re[j] *= inverse * inverse;
    im[j] *= inverse * inverse;
  }
  const double m = sum / grid_;
  const double value = q * m;
  if (!std::isfinite(value)) return kInfinity;
  if (gradient.empty()) return value;
  // d(Q_eff M) / d alpha_k = Q_eff dM / d alpha_k + M dQ_eff / d alpha_k.
  for (int k = 0; k < length_; ++k) {
    const double* er = basis_re_.data() + k * grid;
    const double* ei = basis_im_.data() + k * grid;
    double dot = 0.0;
    for (std::size_t j = 0; j < grid; ++j) dot += re[j] * er[j] + im[j] * ei[j];
    const double dm = -2.0 * dot / grid_;
    const double dq = numerical ? 2.0 * (dt_ + readout_slots_) * gains[k] : dt_;
    gradient[k] = q * dm + m * dq;
  }
  return value;
}

}  // namespace fss
