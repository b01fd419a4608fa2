#pragma once

#include <cstdint>
#include <vector>

namespace fss {

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

}  // namespace fss
