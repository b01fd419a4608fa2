// The predicted error of the restoration (docs/method.md §6, §6b):
//   E[RMSE^2] = RMSE_0^2 + (noise part).
// The exact noise part is sum_j W(j) S(j) / count (noise_weights.h), with each
// pixel's own variance; the stationary approximation of the paper is
// sigma^2 = m Q (100 / snr^2) M, which also gives the image-independent
// figure of merit, the SNR at level 100.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"

namespace fss {

struct SimulationReport;  // simulate.h
class SimulationPlan;     // simulate.h

// Q = dt sum alpha_k^2 (numerical) or dt sum alpha_k (analog): the variance
// of the observation of a unit landscape, in units of 100 / snr^2.
double noise_gain(std::span<const double> gains, double dt, ShutterMode mode);

// sigma = sqrt(m Q (100 / snr^2) M); infinite when M is.
double noise_sigma(double mean_level, double q, double m_amplification, double snr);

// SNR of the restored image of a constant landscape at level 100:
// 100 / sqrt(100 Q (100 / snr^2) M); 0 when M is infinite.
double snr_level100(double q, double m_amplification, double snr);

// The same counting a sensor's readouts (docs/method.md §10). A default
// sensor gives the functions above, bit for bit. Otherwise sigma^2 =
// Var_obs(m) M with Var_obs(m) = (m / 100) V_photon + (V_100 - V_photon),
// V_100 the level-100 observation variance with the sensor
// (level100_observation_variance, sensor.h) and V_photon without it: the
// readouts' terms do not scale with the level m. SNR at level 100:
// 100 / sqrt(V_100 M).
double noise_sigma(double mean_level, std::span<const double> gains, double dt, ShutterMode mode,
                   double m_amplification, double snr, const SensorModel& sensor);
double snr_level100(std::span<const double> gains, double dt, ShutterMode mode,
                    double m_amplification, double snr, const SensorModel& sensor);

// What the noise-free pass of a run measures for the prediction.
struct NoiseFreeRun {
  double rmse = 0.0;  // RMSE_0, the RMSE of the noise-free restoration
  // S(j) for the observed-crop columns j in [0, Wa) (observation column
  // h + j): the sum over rows and channels of the observation noise's
  // variance at that column. Empty for a run without noise.
  std::vector<double> crop_variance_sums;
  // Readouts of the observed crop a sensor with a full well or an ADC clips
  // (ReadoutClipping, observe.h): the prediction is then approximate.
  std::uint64_t saturated_readouts = 0;
  std::uint64_t near_zero_readouts = 0;
};

struct Prediction {
  bool finite = false;           // false for a code that is not invertible
  double window_mean = 0.0;      // m, mean of the ground truth over the RMSE window
  double q = 0.0;                // Q
  double m_amplification = 0.0;  // M, mean of 1 / |K|^2 on the deconvolution grid
  double rmse_noise_free = 0.0;  // RMSE_0, from the noise-free run
  // The exact expected error (§6b): rmse = sqrt(E[MSE]) = sqrt(RMSE_0^2 + noise^2),
  // noise^2 = sum_j W(j) S(j) / (rows * channels * window width).
  double noise = 0.0;
  double rmse = 0.0;
  // The stationary approximation (§6): sigma^2 = m Q (100 / snr^2) M and
  // rmse_stationary = sqrt(RMSE_0^2 + sigma^2).
  double sigma = 0.0;
  double rmse_stationary = 0.0;
  double snr_level100 = 0.0;  // the image-independent figure of merit, from Q and M
  // False when a sensor with a full well or an ADC clips some readout of the
  // observed crop (docs/method.md §10): the variance terms assume a linear
  // readout, so rmse and rmse_stationary are then approximations.
  bool exact = true;
};

// The prediction for the run `report` describes (its options, code, geometry,
// RMSE window and kernel) on `input`, from its noise-free pass. The noise
// parts are 0 without noise, and infinite for a kernel that is not
// invertible. Throws a usage fss::Error for a noisy run whose
// noise_free.crop_variance_sums does not have one value per observed-crop
// column.
Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free);
// The same with M and W(j) from the plan the report was run with.
Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free, const SimulationPlan& plan);

}  // namespace fss
