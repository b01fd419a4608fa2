// The prediction of a run's error from its report and noise-free pass
// (docs/method.md §6, §6b).
#pragma once

#include <vector>

#include "fss/core/image.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/simulate.h"
#include "pipeline/noise_free_run.h"

namespace fss {

// m: the mean of `image`'s columns [first, end) over its rows and channels.
double window_mean(const Image& image, int first, int end);

// sum_j W(j) S(j) / (rows * channels * window width): the noise part of E[MSE] over the RMSE
// window of `report` (docs/method.md §6b), with W(j) = `w` and S(j) from `run`. Throws a usage
// fss::Error when `run` does not have one S(j) per observed-crop column.
double exact_noise_power(const SimulationReport& report, const std::vector<double>& w,
                         const NoiseFreeRun& run);

// The prediction for the run `report` describes (its options, code, geometry,
// RMSE window and kernel) on `input`, from its noise-free pass. The noise
// parts are 0 without noise, and infinite for a kernel that is not
// invertible. Throws a usage fss::Error for a noisy run whose
// noise_free.crop_variance_sums does not have one value per observed-crop
// column.
Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free);
// The same with M and W(j) of the filter the run restored with (its plan's or its fitted filter,
// any restoration of docs/method.md §12; the overload above is the inverse filter's).
Prediction predict(const SimulationReport& report, const Image& input,
                   const NoiseFreeRun& noise_free, double m_amplification,
                   const std::vector<double>& noise_weights);

}  // namespace fss
