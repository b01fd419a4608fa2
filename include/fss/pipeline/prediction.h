// The predicted error of the restoration (docs/method.md §6, §6b): the paper's stationary
// formulas, with its figure of merit (the SNR at level 100), and the Prediction a run reports.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "fss/model/code.h"
#include "fss/model/sensor.h"

namespace fss {

// Q = dt sum alpha_k^2 (numerical) or dt sum alpha_k (analog): the variance
// of the observation of a unit landscape, in units of 100 / snr^2.
double noise_gain(std::span<const double> gains, double dt, ShutterMode mode);

// sigma = sqrt(m Q (100 / snr^2) M) (a mean level m < 0 counts as 0); infinite when M is.
double noise_sigma(double mean_level, double q, double m_amplification, double snr);

// SNR of the restored image of a constant landscape at level 100:
// 100 / sqrt(100 Q (100 / snr^2) M); 0 when M is infinite.
double snr_level100(double q, double m_amplification, double snr);

// The same counting a sensor's readouts (docs/method.md §10); a default sensor gives the
// functions above, bit for bit. sigma^2 = ((m / 100) V_photon + V_100 - V_photon) M and the SNR
// at level 100 is 100 / sqrt(V_100 M), V_100 the level100_observation_variance (sensor.h) with
// the sensor and V_photon without it.
double noise_sigma(double mean_level, std::span<const double> gains, double dt, ShutterMode mode,
                   double m_amplification, double snr, const SensorModel& sensor);
double snr_level100(std::span<const double> gains, double dt, ShutterMode mode,
                    double m_amplification, double snr, const SensorModel& sensor);

struct Prediction {
  bool finite = false;           // false for a code that is not invertible
  double window_mean = 0.0;      // m, mean of the ground truth over the RMSE window
  double q = 0.0;                // Q
  double m_amplification = 0.0;  // M, mean of 1 / |K|^2 on the deconvolution grid
  double rmse_noise_free = 0.0;  // RMSE_0, from the noise-free run
  // The exact expected error (§6b): rmse = sqrt(E[MSE]) = sqrt(RMSE_0^2 + noise^2).
  double noise = 0.0;
  double rmse = 0.0;
  // The stationary approximation (§6): sigma^2 = m Q (100 / snr^2) M and
  // rmse_stationary = sqrt(RMSE_0^2 + sigma^2).
  double sigma = 0.0;
  double rmse_stationary = 0.0;
  double snr_level100 = 0.0;  // the image-independent figure of merit, from Q and M
  // False when a sensor's full well or ADC clips some readout of the observed crop
  // (docs/method.md §10): rmse and rmse_stationary are then approximations.
  bool exact = true;
  // Under a velocity distribution (docs/method.md §13): E[MSE] averaged over the distribution
  // (infinite when the code is not invertible over a part of the support of positive
  // probability), rmse = sqrt(mse), and the adaptive quadrature's error estimate and
  // evaluations (expected_over_velocity, model/velocity_distribution.h). The other fields are
  // then averaged alike: m_amplification = E[M], rmse_noise_free = sqrt(E[RMSE_0^2]), noise =
  // sqrt(E[noise^2]), sigma and rmse_stationary from E[M], snr_level100 = snr / sqrt(Q E[M]).
  // Empty without a distribution.
  // mse_evaluations counts the noise-free passes, one per velocity (each made once). When mse is
  // infinite, mse_infinite_reason says where the code is not invertible ("code not invertible
  // at velocity 1.5 of the support", or "... at the restore velocity 1.2"), no velocity is
  // evaluated, and the averaged fields but window_mean and q are infinite (rmse_noise_free
  // included: not computed); "" otherwise.
  std::optional<double> mse;
  double mse_error_estimate = 0.0;
  int mse_evaluations = 0;
  std::string mse_infinite_reason;
};

}  // namespace fss
