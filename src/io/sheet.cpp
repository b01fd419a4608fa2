#include "io/sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/model/restoration.h"

namespace fss {

namespace {

// The smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 times a power of ten that
// is >= `value` (> 0): a bound whose half and quarter print short.
double nice_ceiling(double value) {
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (const double step : {1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0}) {
    if (step * decade >= value) return step * decade;
  }
  return 10.0 * decade;
}

// The residual d = ground truth - restored shown on a symmetric scale: gray
// 127.5 + 127.5 d / R, R the largest |d| rounded up by nice_ceiling (1 when d
// is 0 everywhere), so mid-gray is 0 and nothing is clipped. Returns R.
double symmetric_residual(const Image& truth, const Image& restored, Image* shown) {
  double largest = 0.0;
  for (std::size_t i = 0; i < truth.data.size(); ++i) {
    largest = std::max(largest, std::abs(truth.data[i] - restored.data[i]));
  }
  const double range = largest > 0.0 && std::isfinite(largest) ? nice_ceiling(largest) : 1.0;
  *shown = Image(truth.width, truth.height, truth.channels);
  for (std::size_t i = 0; i < truth.data.size(); ++i) {
    shown->data[i] = 127.5 + 127.5 * (truth.data[i] - restored.data[i]) / range;
  }
  return range;
}

}  // namespace

std::vector<std::uint8_t> figure_sheet_png(const SimulationReport& r, const Image& input) {
  if (r.observed.data.empty()) {
    throw_usage_error(
        "sheet.png needs the observed image: run Simulate without an ObservedRowSink");
  }
  char parameters[160];
  std::snprintf(parameters, sizeof parameters,
                "%s, v = %g, dt = %g, snr = %g: RMSE %.4g, RMSE_CI %.4g",
                to_string(r.options.mode).c_str(), first_trial_velocity(r.options), r.options.dt,
                r.options.snr, r.metrics.rmse, r.metrics.rmse_ci);
  Image residual;
  const double range = symmetric_residual(groundtruth_image(input, r), r.restored, &residual);
  const RestorationMethod method = r.restoration.options.method;
  const std::string restored = method == RestorationMethod::kInverse
                                   ? "restored (inverse filter)"
                                   : "restored (" + to_string(method) + " filter)";
  const SheetScale scale{-range, range,
                         r.restored.channels == 1 ? "gray levels" : "levels of each channel"};
  return figure_sheet_png({{&r.observed, "observed ÷ K(0)"},
                           {&r.restored, restored},
                           {&residual, "residual: ground truth − restored", scale}},
                          r.code_name + " — " + parameters);
}

}  // namespace fss
