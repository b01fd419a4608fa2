// code.png and spectrum.png of a run, drawn ahead of write_outputs.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// code.png and spectrum.png of a run. They depend only on the code and the
// motion, so a caller can draw them on another thread while Simulate runs
// and hand them to write_outputs (OutputOptions::rendered_plots). Drawing
// is serialized inside PLplot: it overlaps the simulation, not other plots.
struct RunPlots {
  std::string code_name;  // what they were drawn for, checked by write_outputs
  std::vector<double> gains;
  double velocity_px_per_slot = 0.0;
  double restore_velocity_px_per_slot = 0.0;
  double dt = 0.0;
  std::vector<std::uint8_t> code_png;
  std::vector<std::uint8_t> spectrum_png;
};

// Draws the plots write_outputs would draw for a run of `code` with
// `options`: the same bytes.
RunPlots render_run_plots(const ShutterCode& code, const SimulationOptions& options);

// code.png of the report's run: the plot drawn ahead when there is one,
// else drawn now; likewise spectrum.png. Plots drawn for another code or
// motion than the report's are a usage error naming the difference.
std::vector<std::uint8_t> run_code_png(const SimulationReport& report,
                                       const std::optional<RunPlots>& drawn_ahead);
std::vector<std::uint8_t> run_spectrum_png(const SimulationReport& report,
                                           const std::optional<RunPlots>& drawn_ahead);
// The same, the plots drawn ahead given by address (null: none).
std::vector<std::uint8_t> run_code_png(const SimulationReport& report, const RunPlots* drawn_ahead);
std::vector<std::uint8_t> run_spectrum_png(const SimulationReport& report,
                                           const RunPlots* drawn_ahead);

}  // namespace fss
