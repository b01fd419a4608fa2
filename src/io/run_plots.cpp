#include "io/run_plots.h"

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/model/kernel.h"

namespace fss {

namespace {

// The velocities of the report's images (under a velocity distribution, the first trial's).
double restore_velocity_of(const SimulationOptions& o) {
  return o.restore_velocity_px_per_slot.value_or(first_trial_velocity(o));
}

// What differs between the run `plots` were drawn for and the report's run;
// empty if nothing.
std::string difference(const RunPlots& plots, const SimulationReport& report) {
  const SimulationOptions& o = report.options;
  const double restore_velocity = restore_velocity_of(o);
  if (plots.code_name != report.code_name) {
    return "code '" + plots.code_name + "', the run's is '" + report.code_name + "'";
  }
  if (plots.gains != report.gains) return "other gains of code '" + plots.code_name + "'";
  if (plots.velocity_px_per_slot != first_trial_velocity(o)) {
    return "velocity " + format_exact(plots.velocity_px_per_slot) + ", the run's is " +
           format_exact(first_trial_velocity(o));
  }
  if (plots.restore_velocity_px_per_slot != restore_velocity) {
    return "restore velocity " + format_exact(plots.restore_velocity_px_per_slot) +
           ", the run's is " + format_exact(restore_velocity);
  }
  if (plots.dt != o.dt) {
    return "dt " + format_exact(plots.dt) + ", the run's is " + format_exact(o.dt);
  }
  return "";
}

const RunPlots& checked(const RunPlots& plots, const SimulationReport& report) {
  const std::string problem = difference(plots, report);
  if (!problem.empty()) {
    throw_usage_error("the plots given to write_outputs are not for the report's run: drawn for " +
                      problem);
  }
  return plots;
}

}  // namespace

RunPlots render_run_plots(const ShutterCode& code, const SimulationOptions& options) {
  RunPlots plots;
  plots.code_name = code.name;
  plots.gains = code.gains;
  plots.velocity_px_per_slot = first_trial_velocity(options);
  plots.restore_velocity_px_per_slot = restore_velocity_of(options);
  plots.dt = options.dt;
  plots.code_png = plot_code_png(code.gains, code.name);
  // The curve at the true velocity; the minimum marked is that of the
  // kernel the restoration inverts (SimulationReport::kernel).
  plots.spectrum_png =
      plot_spectrum_png(code.gains, code.name, plots.velocity_px_per_slot, plots.dt,
                        analyze_kernel(code.gains, plots.restore_velocity_px_per_slot, plots.dt));
  return plots;
}

std::vector<std::uint8_t> run_code_png(const SimulationReport& report,
                                       const std::optional<RunPlots>& drawn_ahead) {
  return run_code_png(report, drawn_ahead ? &*drawn_ahead : nullptr);
}

std::vector<std::uint8_t> run_spectrum_png(const SimulationReport& report,
                                           const std::optional<RunPlots>& drawn_ahead) {
  return run_spectrum_png(report, drawn_ahead ? &*drawn_ahead : nullptr);
}

std::vector<std::uint8_t> run_code_png(const SimulationReport& report,
                                       const RunPlots* drawn_ahead) {
  if (drawn_ahead != nullptr) return checked(*drawn_ahead, report).code_png;
  return plot_code_png(report.gains, report.code_name);
}

std::vector<std::uint8_t> run_spectrum_png(const SimulationReport& report,
                                           const RunPlots* drawn_ahead) {
  if (drawn_ahead != nullptr) return checked(*drawn_ahead, report).spectrum_png;
  return plot_spectrum_png(report.gains, report.code_name, first_trial_velocity(report.options),
                           report.options.dt, report.kernel);
}

}  // namespace fss
