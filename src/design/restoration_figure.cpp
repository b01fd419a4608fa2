// The stationary figures of merit of the Wiener and Tikhonov restorations (design/analyze.h,
// design/restoration_figure.h; docs/method.md §12).
#include "design/restoration_figure.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/golden_section.h"
#include "design/local_search.h"
#include "fss/core/error.h"
#include "fss/design/analyze.h"
#include "fss/model/kernel.h"
#include "fss/model/sensor.h"
#include "fss/model/transfer.h"

namespace fss {

namespace design_detail {

namespace {

// The search of the optimal lambda: a grid of kLambdaNodesPerDecade nodes a decade in log lambda
// over [kMinRegularization, kMaxRegularization], then kGoldenSteps golden-section steps between
// the best node's neighbours (the bracket shrinks by 0.618^40, to 1e-8 of its width).
constexpr int kLambdaNodesPerDecade = 4;
constexpr int kGoldenSteps = 40;

}  // namespace

BandRestoration::BandRestoration(const RestorationOptions& restoration, int grid_points) {
  check_design_restoration(restoration);
  if (restoration.method == RestorationMethod::kInverse) {
    throw_usage_error("BandRestoration: the inverse filter's figure is Q_eff M, not a band prior");
  }
  if (grid_points < 1) {
    throw_usage_error("the restoration figure needs a band grid of at least 1 node, got " +
                      std::to_string(grid_points));
  }
  tikhonov_ = restoration.method == RestorationMethod::kTikhonov;
  lambda_ = restoration.regularization.value_or(0.0);
  const double gamma = restoration.prior_exponent;
  const double level = restoration.prior_level.value_or(kDefaultPriorLevel);
  prior_.resize(static_cast<std::size_t>(grid_points));
  inverse_prior_.resize(static_cast<std::size_t>(grid_points));
  for (int j = 0; j < grid_points; ++j) {
    const double xi = (j + 0.5) * M_PI / grid_points;
    // S_j = C xi_j^-gamma
    prior_[j] = level * std::pow(xi, -gamma);
    inverse_prior_[j] = std::pow(xi, gamma) / level;
  }
}

// E(mu) = (1 / G) sum_j (mu^2 S_j + P_j V) / (P_j + mu)^2, written as
// S_j (mu / (P_j + mu))^2 + (V / (P_j + mu)) (P_j / (P_j + mu)) so that no square or product of
// two large or two small numbers is formed (the scale of the gains cancels).
double BandRestoration::TikhonovError(std::span<const double> power, double noise,
                                      double mu) const {
  double sum = 0.0;
  for (std::size_t j = 0; j < prior_.size(); ++j) {
    const double total = power[j] + mu;
    const double bias = mu / total;
    sum += prior_[j] * bias * bias + (noise / total) * (power[j] / total);
  }
  return sum / static_cast<double>(prior_.size());
}

// The lambda in [kMinRegularization, kMaxRegularization] minimising E(lambda kappa^2): the best
// node of the grid in log lambda, then the golden section between its neighbours; the better of
// the two ends it.
double BandRestoration::OptimalLambda(std::span<const double> power, double noise, double kappa,
                                      double* error) const {
  const double low = std::log(kMinRegularization);
  const double high = std::log(kMaxRegularization);
  const int nodes =
      1 + static_cast<int>(std::lround(kLambdaNodesPerDecade *
                                       std::log10(kMaxRegularization / kMinRegularization)));
  const auto node = [&](int i) { return low + (high - low) * i / (nodes - 1); };
  const auto at = [&](double u) {
    return TikhonovError(
        power, noise,
        std::clamp(std::exp(u), kMinRegularization, kMaxRegularization) * kappa * kappa);
  };
  int best = 0;
  double best_error = kInfinity;
  for (int i = 0; i < nodes; ++i) {
    const double e = at(node(i));
    if (e < best_error) {
      best = i;
      best_error = e;
    }
  }
  double best_u = node(best);
  const auto [u, e] = golden_section_minimum(
      at, node(std::max(best - 1, 0)), node(std::min(best + 1, nodes - 1)), kGoldenSteps, 0.0);
  if (e < best_error) {
    best_u = u;
    best_error = e;
  }
  *error = best_error;
  return std::clamp(std::exp(best_u), kMinRegularization, kMaxRegularization);
}

BandRestoration::Figure BandRestoration::Evaluate(std::span<const double> power, double noise,
                                                  double kappa) const {
  if (!(noise > 0.0) || !(kappa > 0.0)) return {kInfinity, 0.0};
  Figure figure;
  if (tikhonov_) {
    if (lambda_ > 0.0) {
      figure.lambda = lambda_;
      figure.error = TikhonovError(power, noise, lambda_ * kappa * kappa);
    } else {
      figure.lambda = OptimalLambda(power, noise, kappa, &figure.error);
    }
    return figure;
  }
  // Wiener: e_j = V / (P_j + V / S_j), S_j where K vanishes.
  double sum = 0.0;
  for (std::size_t j = 0; j < inverse_prior_.size(); ++j) {
    sum += noise / (power[j] + noise * inverse_prior_[j]);
  }
  figure.error = sum / static_cast<double>(inverse_prior_.size());
  return figure;
}

// Wiener, with D = P + V / S:   de/dP = -V / D^2,  de/dV = P / D^2.
// Tikhonov, with T = P + mu, b = mu / T:
//   de/dP = (V (mu - P) - 2 mu^2 S) / T^3 = (V (mu - P) / T^2 - 2 S b^2) / T,
//   de/dV = P / T^2,
//   de/dmu = 2 P (mu S - V) / T^3 = 2 (P / T) (S b - V / T) / T,
// and dmu/dkappa = 2 lambda kappa.
double BandRestoration::Derivatives(std::span<const double> power, double noise, double kappa,
                                    double lambda, std::span<double> d_power,
                                    double* d_kappa) const {
  const double g = static_cast<double>(prior_.size());
  double d_noise = 0.0;
  double d_mu = 0.0;
  const double mu = lambda * kappa * kappa;
  for (std::size_t j = 0; j < prior_.size(); ++j) {
    const double p = power[j];
    if (tikhonov_) {
      const double total = p + mu;
      const double b = mu / total;
      d_power[j] = ((noise / total) * ((mu - p) / total) - 2.0 * prior_[j] * b * b) / total / g;
      d_noise += (p / total) / total;
      d_mu += 2.0 * (p / total) * (prior_[j] * b - noise / total) / total;
    } else {
      const double denominator = p + noise * inverse_prior_[j];
      d_power[j] = -(noise / denominator) / denominator / g;
      d_noise += (p / denominator) / denominator;
    }
  }
  *d_kappa = tikhonov_ ? d_mu / g * 2.0 * lambda * kappa : 0.0;
  return d_noise / g;
}

RestorationObjective::RestorationObjective(int length, double velocity, double dt, ShutterMode mode,
                                           double snr, const RestorationOptions& restoration,
                                           int grid_points, double readout_slots)
    : length_(length),
      grid_(grid_points),
      dt_(dt),
      readout_slots_(readout_slots),
      noise_per_q_(1.0e4 / snr / snr),
      mode_(mode),
      band_(restoration, grid_points) {
  if (length < 1) {
    throw_usage_error("the restoration figure needs a code of at least 1 gain, got " +
                      std::to_string(length));
  }
  if (!(std::isfinite(readout_slots) && readout_slots >= 0.0)) {
    throw_usage_error("the readout noise of the restoration figure, " +
                      format_number(readout_slots) +
                      " slots of level-100 light, must be finite and >= 0");
  }
  make_band_basis(length, velocity, dt, grid_points, &basis_re_, &basis_im_);
}

// K_j = sum_k alpha_k E_jk on the grid.
void RestorationObjective::Transfer(std::span<const double> gains, std::vector<double>* re,
                                    std::vector<double>* im) const {
  const std::size_t grid = static_cast<std::size_t>(grid_);
  re->assign(grid, 0.0);
  im->assign(grid, 0.0);
  for (int k = 0; k < length_; ++k) {
    if (gains[k] == 0.0) continue;
    const double* er = basis_re_.data() + k * grid;
    const double* ei = basis_im_.data() + k * grid;
    for (std::size_t j = 0; j < grid; ++j) {
      (*re)[j] += gains[k] * er[j];
      (*im)[j] += gains[k] * ei[j];
    }
  }
}

// dE/d alpha_k = sum_j dE/dP_j 2 Re(conj(K_j) E_jk) + dE/dV (10^4 / snr^2) dQ_eff/d alpha_k
//                + dE/dkappa dt sign(alpha_k),
// dQ_eff / d alpha_k = 2 (dt + c) alpha_k (numerical) or dt (analog).
void RestorationObjective::Gradient(std::span<const double> gains, const std::vector<double>& re,
                                    const std::vector<double>& im, std::span<const double> d_power,
                                    double d_noise, double d_kappa,
                                    std::span<double> gradient) const {
  const std::size_t grid = static_cast<std::size_t>(grid_);
  const bool numerical = mode_ == ShutterMode::kNumerical;
  for (int k = 0; k < length_; ++k) {
    const double* er = basis_re_.data() + k * grid;
    const double* ei = basis_im_.data() + k * grid;
    double dot = 0.0;
    for (std::size_t j = 0; j < grid; ++j) dot += d_power[j] * (re[j] * er[j] + im[j] * ei[j]);
    const double dq = numerical ? 2.0 * (dt_ + readout_slots_) * gains[k] : dt_;
    const double sign = gains[k] > 0.0 ? 1.0 : (gains[k] < 0.0 ? -1.0 : 0.0);
    gradient[k] = 2.0 * dot + d_noise * noise_per_q_ * dq + d_kappa * dt_ * sign;
  }
}

// E = BandRestoration's figure for P_j = |K_j|^2, V = (10^4 / snr^2) Q_eff, kappa = dt sum |alpha|.
double RestorationObjective::Evaluate(std::span<const double> gains, std::span<double> gradient,
                                      double* lambda) const {
  if (static_cast<int>(gains.size()) != length_ ||
      (!gradient.empty() && static_cast<int>(gradient.size()) != length_)) {
    throw_usage_error("RestorationObjective::Evaluate: expected " + std::to_string(length_) +
                      " gains");
  }
  std::vector<double> re, im;
  Transfer(gains, &re, &im);
  // Q_eff = (dt + c) sum alpha^2 (numerical) or dt sum alpha + c (analog).
  const bool numerical = mode_ == ShutterMode::kNumerical;
  double q = 0.0;
  double kappa = 0.0;
  for (const double alpha : gains) {
    q += numerical ? alpha * alpha : alpha;
    kappa += std::abs(alpha);
  }
  q = numerical ? q * (dt_ + readout_slots_) : q * dt_ + readout_slots_;
  kappa *= dt_;
  if (!(q > 0.0)) return kInfinity;
  std::vector<double> power(re.size());
  for (std::size_t j = 0; j < re.size(); ++j) power[j] = re[j] * re[j] + im[j] * im[j];
  const double noise = noise_per_q_ * q;
  const BandRestoration::Figure figure = band_.Evaluate(power, noise, kappa);
  if (lambda != nullptr) *lambda = figure.lambda;
  if (!std::isfinite(figure.error)) return kInfinity;
  if (gradient.empty()) return figure.error;
  std::vector<double> d_power(re.size());
  double d_kappa = 0.0;
  const double d_noise = band_.Derivatives(power, noise, kappa, figure.lambda, d_power, &d_kappa);
  Gradient(gains, re, im, d_power, d_noise, d_kappa, gradient);
  return figure.error;
}

}  // namespace design_detail

void check_design_restoration(const RestorationOptions& restoration) {
  std::string error;
  if (!restoration.IsValid(&error)) throw_usage_error(error);
  if (restoration.method == RestorationMethod::kWiener && restoration.prior == PriorKind::kOracle) {
    throw_usage_error(
        "prior = oracle: code design has no image, so there is no oracle spectrum (use a "
        "power-law prior)");
  }
}

std::string describe_design_criterion(const RestorationOptions& restoration) {
  const std::string prior = "power-law prior gamma " + format_exact(restoration.prior_exponent) +
                            ", C " +
                            format_exact(restoration.prior_level.value_or(kDefaultPriorLevel));
  switch (restoration.method) {
    case RestorationMethod::kInverse:
      return "inverse filter (stationary noise at level 100)";
    case RestorationMethod::kWiener:
      return "wiener restoration, " + prior + " (stationary expected error at level 100)";
    case RestorationMethod::kTikhonov:
      return "tikhonov restoration, lambda " +
             (restoration.regularization ? format_exact(*restoration.regularization)
                                         : "optimal in [" + format_exact(kMinRegularization) +
                                               ", " + format_exact(kMaxRegularization) + "]") +
             ", its bias measured under the default " + prior +
             " (stationary expected error at level 100)";
  }
  return "";
}

RestorationError level100_restoration_error(std::span<const double> gains, double velocity,
                                            double dt, double snr, ShutterMode mode,
                                            const RestorationOptions& restoration,
                                            const SensorModel& sensor) {
  check_design_restoration(restoration);
  check_design_sensor(sensor);
  if (!std::isfinite(velocity) || !(std::isfinite(dt) && dt > 0.0) ||
      !(std::isfinite(snr) && snr > 0.0) || gains.empty()) {
    throw_usage_error(
        "level100_restoration_error: needs gains, a finite velocity, dt > 0 and "
        "snr > 0, got velocity " +
        format_exact(velocity) + ", dt " + format_exact(dt) + ", snr " + format_exact(snr));
  }
  // V: the variance of the level-100 observation, photon noise and readouts (§10).
  const double noise = level100_observation_variance(gains, dt, mode, snr, sensor);
  if (restoration.method == RestorationMethod::kInverse) {
    // As analyze_code: a code with a zero on the band has no finite M, whatever the nodes see.
    if (!analyze_kernel(gains, velocity, dt).invertible) return {design_detail::kInfinity, 0.0};
    const double m = band_mean_inverse_power(gains, velocity, dt);
    return {std::isfinite(m) ? noise * m : design_detail::kInfinity, 0.0};
  }
  // K(0) = dt sum alpha_k = 0 (a numerical code of zero sum) loses the mean level, where the
  // prior's power c |xi|^-gamma is not integrable for gamma >= 1: E is infinite there, whatever
  // the nodes see.
  double sum = 0.0;
  for (const double alpha : gains) sum += alpha;
  const double k0 = dt * sum;
  if (restoration.prior_exponent >= 1.0 &&
      transfer_vanishes(std::abs(k0), transfer_scale(gains, dt))) {
    return {design_detail::kInfinity, restoration.regularization.value_or(0.0)};
  }
  const design_detail::BandRestoration band(restoration, kBandGridPoints);
  std::vector<double> power(static_cast<std::size_t>(kBandGridPoints));
  for (int j = 0; j < kBandGridPoints; ++j) {
    const double xi = (j + 0.5) * M_PI / kBandGridPoints;
    power[j] = std::norm(transfer_function(gains, velocity, dt, xi));
  }
  const design_detail::BandRestoration::Figure figure =
      band.Evaluate(power, noise, transfer_scale(gains, dt));
  return {figure.error, figure.lambda};
}

}  // namespace fss
