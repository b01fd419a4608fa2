#include "io/sheet.h"

#include <cstdio>
#include <string>

#include "fss/core/error.h"
#include "fss/io/plot.h"

namespace fss {

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
  const Image residual = residual_image(input, r);
  return figure_sheet_png(
      {{&r.observed, "observed"}, {&r.restored, "restored"}, {&residual, "residual (stretched)"}},
      r.code_name + " — " + parameters);
}

}  // namespace fss
