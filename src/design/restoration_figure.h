// The stationary figures of merit of the Wiener and Tikhonov restorations for code design
// (design/analyze.h, level100_restoration_error), and the optimizer's objective under them, with
// its gradient; not part of the public interface. docs/method.md §12.
#pragma once

#include <span>
#include <vector>

#include "fss/model/code.h"
#include "fss/model/restoration.h"

namespace fss::design_detail {

// The level-100 error E of a Wiener or Tikhonov restoration on the midpoint band grid
// xi_j = (j + 1/2) pi / G, j < G (the integrands are even in xi, so (1/2 pi) int_{-pi}^{pi} is the
// mean over the G nodes), from P_j = |K(xi_j)|^2, the observation noise V and kappa:
//   wiener:   e_j = V S_j / (P_j S_j + V) = V / (P_j + V / S_j),
//   tikhonov: e_j = (mu^2 S_j + P_j V) / (P_j + mu)^2, mu = lambda kappa^2,
// with the power-law prior S_j = C xi_j^-gamma, and E = (1 / G) sum_j e_j.
class BandRestoration {
 public:
  // `restoration` is Wiener (power-law prior) or Tikhonov (its lambda, or none for the optimal
  // one); C = prior_level or kDefaultPriorLevel. Throws a usage fss::Error for the inverse
  // filter, an oracle prior, options RestorationOptions::IsValid refuses or grid_points < 1.
  BandRestoration(const RestorationOptions& restoration, int grid_points);

  int grid_points() const { return static_cast<int>(inverse_prior_.size()); }

  struct Figure {
    double error = 0.0;   // E, gray levels^2; infinite when V <= 0 or kappa <= 0
    double lambda = 0.0;  // tikhonov: the lambda of E (the optimal one without a given lambda)
  };
  // E for P_j = power[j] (grid_points() values), V = noise and kappa = dt sum |alpha_k|.
  Figure Evaluate(std::span<const double> power, double noise, double kappa) const;

  // The partial derivatives of E at a fixed lambda (0 for Wiener): dE/dP_j into d_power
  // (grid_points() values), dE/dkappa into *d_kappa (0 for Wiener); returns dE/dV. For the optimal
  // lambda these are the derivatives of the minimum over lambda (the envelope theorem, the range
  // of lambda not depending on the code).
  double Derivatives(std::span<const double> power, double noise, double kappa, double lambda,
                     std::span<double> d_power, double* d_kappa) const;

 private:
  double TikhonovError(std::span<const double> power, double noise, double mu) const;
  double OptimalLambda(std::span<const double> power, double noise, double kappa,
                       double* error) const;

  bool tikhonov_ = false;
  double lambda_ = 0.0;                // a given lambda; 0: the optimal one
  std::vector<double> prior_;          // S_j = C xi_j^-gamma
  std::vector<double> inverse_prior_;  // 1 / S_j = xi_j^gamma / C
};

// The optimizer's objective under a Wiener or Tikhonov restoration: E of a code of fixed length
// on the midpoint band grid, with its gradient. V = (10^4 / snr^2) Q_eff, Q_eff = (dt + c) sum
// alpha^2 (numerical) or dt sum alpha + c (analog), c = readout_slots (docs/method.md §10), and
// K_j = sum_k alpha_k E_jk on the basis of make_band_basis (local_search.h).
class RestorationObjective {
 public:
  RestorationObjective(int length, double velocity, double dt, ShutterMode mode, double snr,
                       const RestorationOptions& restoration, int grid_points,
                       double readout_slots = 0.0);

  int length() const { return length_; }
  const BandRestoration& band() const { return band_; }
  // 10^4 / snr^2: V per unit of Q_eff.
  double noise_per_q() const { return noise_per_q_; }

  // E of `gains` (length() values); +infinity when Q_eff <= 0 or E is not finite. A non-empty
  // `gradient` receives dE / d alpha, unspecified for an infinite value; `lambda` (when not null)
  // the Tikhonov lambda. Other sizes are a usage fss::Error.
  double Evaluate(std::span<const double> gains, std::span<double> gradient = {},
                  double* lambda = nullptr) const;

 private:
  void Transfer(std::span<const double> gains, std::vector<double>* re,
                std::vector<double>* im) const;
  void Gradient(std::span<const double> gains, const std::vector<double>& re,
                const std::vector<double>& im, std::span<const double> d_power, double d_noise,
                double d_kappa, std::span<double> gradient) const;

  int length_;
  int grid_;
  double dt_;
  double readout_slots_;
  double noise_per_q_;
  ShutterMode mode_;
  BandRestoration band_;
  std::vector<double> basis_re_;  // E_jk, row k holds the grid_ nodes j
  std::vector<double> basis_im_;
};

}  // namespace fss::design_detail
