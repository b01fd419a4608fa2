#include <sstream>
#include <string>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// The ground truth and the residual are derived from the input on demand rather than kept in
// the report: for a large image each would be as big as the input.
Image groundtruth_image(const Image& input, const SimulationReport& report) {
  return crop_columns(input, report.output_first_column(), report.geometry.output_width);
}

Image residual_image(const Image& input, const SimulationReport& report) {
  return residual_display(groundtruth_image(input, report), report.restored);
}

std::string SimulationReport::FullReport() const {
  std::ostringstream out;
  out << "fssim simulation report\n";
  out << "  input            " << width << " x " << height << ", " << channels
      << (channels == 1 ? " channel\n" : " channels\n");
  out << "  code             " << code_name << " (L = " << gains.size()
      << ", sum = " << format_number(gain_sum(gains))
      << ", normalized L1 = " << format_number(normalized_l1(gains)) << ")\n";
  const std::string velocity =
      options.velocity_distribution
          ? "drawn by each trial from the " + options.velocity_distribution->describe() +
                " (the first trial's " + format_number(first_trial_velocity(options)) + ")"
          : format_number(options.velocity_px_per_slot);
  out << "  mode             " << to_string(options.mode) << ", velocity " << velocity
      << (options.restore_velocity_px_per_slot
              ? " (restored as " + format_number(*options.restore_velocity_px_per_slot) + ")"
              : std::string())
      << ", dt " << format_number(options.dt) << ", snr " << format_number(options.snr)
      << ", noise " << to_string(options.noise) << ", seed " << options.seed << "\n";
  if (options.sensor.enabled()) {  // docs/method.md §10
    const SensorModel& s = options.sensor;
    out << "  sensor           read noise " << format_number(s.read_noise_electrons)
        << " e-, dark current " << format_number(s.dark_current_electrons_per_slot)
        << " e-/slot, full well "
        << (s.full_well_electrons ? format_number(*s.full_well_electrons) + " e-" : "none")
        << ", ADC "
        << (s.adc_bits != 0 ? std::to_string(s.adc_bits) + " bits, " +
                                  format_number(s.adc_gain_electrons_per_count) + " e-/count"
                            : "none")
        << "\n";
  }
  out << "  geometry         B = " << geometry.blur_length << ", observed crop "
      << geometry.observed_width << ", deconvolution grid " << geometry.mirror_width << ", output "
      << geometry.output_width << "\n";
  out << "  windows          RMSE columns [" << rmse_first << ", " << rmse_end
      << "), RMSE_CI columns [" << rmse_ci_first << ", " << rmse_ci_end << ")\n";
  out << "  kernel           K(0) = " << format_number(kernel.k0)
      << ", min |K| = " << format_number(kernel.min_abs)
      << " at xi = " << format_number(kernel.min_abs_xi)
      << (kernel.invertible ? ", invertible\n" : ", NOT invertible\n");
  out << "  measured         RMSE " << format_number(metrics.rmse) << " (PSNR "
      << format_number(metrics.psnr) << "), RMSE_CI " << format_number(metrics.rmse_ci) << " (PSNR "
      << format_number(metrics.psnr_ci) << ")\n";
  if (trials.n > 1) {
    out << "  trials           n = " << trials.n << ", RMSE " << format_number(trials.rmse_mean)
        << " +/- " << format_number(trials.rmse_sd) << ", RMSE_CI "
        << format_number(trials.rmse_ci_mean) << " +/- " << format_number(trials.rmse_ci_sd)
        << "\n";
  }
  if (trials.mse_mean) {  // under a velocity distribution (docs/method.md §13)
    out << "  trials' MSE      mean " << format_number(*trials.mse_mean) << " +/- "
        << format_number(trials.mse_sd.value_or(0.0)) << " (sd), predicted E[MSE] "
        << (prediction.finite && prediction.mse
                ? format_number(*prediction.mse) + " (" +
                      std::to_string(prediction.mse_evaluations) + " velocities evaluated)"
                : "infinite: " + prediction.mse_infinite_reason)
        << "\n";
  }
  if (prediction.finite) {
    out << "  predicted        RMSE " << format_number(prediction.rmse) << " = sqrt("
        << format_number(prediction.rmse_noise_free) << "^2 + " << format_number(prediction.noise)
        << (prediction.exact ? "^2), the exact expectation\n"
                             : "^2), approximate: the sensor clips readouts\n");
    out << "  stationary       RMSE " << format_number(prediction.rmse_stationary) << " = sqrt("
        << format_number(prediction.rmse_noise_free) << "^2 + " << format_number(prediction.sigma)
        << "^2), SNR at level 100 " << format_number(prediction.snr_level100) << "\n";
  } else {
    out << "  predicted        none: the code is not invertible (infinite noise)\n";
  }
  for (const auto& w : warnings) out << "  warning          " << w << "\n";
  return out.str();
}

}  // namespace fss
