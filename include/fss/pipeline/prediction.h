// The exact (theoretical) error of the restoration (docs/method.md §6):
//   E[RMSE^2] = RMSE_0^2 + sigma^2,  sigma^2 = m Q (100 / snr^2) M.
#pragma once

#include <span>

#include "fss/core/image.h"
#include "fss/model/code.h"

namespace fss {

struct SimulationReport;  // simulate.h

// Q = dt sum alpha_k^2 (numerical) or dt sum alpha_k (analog): the variance
// of the observation of a unit landscape, in units of 100 / snr^2.
double noise_gain(std::span<const double> gains, double dt, ShutterMode mode);

// sigma = sqrt(m Q (100 / snr^2) M); infinite when M is.
double noise_sigma(double mean_level, double q, double m_amplification, double snr);

// SNR of the restored image of a constant landscape at level 100:
// 100 / sqrt(100 Q (100 / snr^2) M); 0 when M is infinite.
double snr_level100(double q, double m_amplification, double snr);

struct Prediction {
  bool finite = false;           // false for a code that is not invertible
  double window_mean = 0.0;      // m, mean of the ground truth over the RMSE window
  double q = 0.0;                // Q
  double m_amplification = 0.0;  // M, mean of 1 / |K|^2 on the deconvolution grid
  double rmse_noise_free = 0.0;  // RMSE_0, from the noise-free run
  double sigma = 0.0;            // noise part
  double rmse = 0.0;             // sqrt(RMSE_0^2 + sigma^2)
  double snr_level100 = 0.0;
};

// The prediction for the run `report` describes (its options, code, geometry,
// RMSE window and kernel) on `input`, given RMSE_0, the RMSE of the
// noise-free restoration. sigma is 0 without noise; sigma and the RMSE are
// infinite for a kernel that is not invertible.
Prediction predict(const SimulationReport& report, const Image& input, double rmse_noise_free);

}  // namespace fss
