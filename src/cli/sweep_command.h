// `fssim sweep`: the simulator over a grid of velocities and snr values (or of snr values under
// a velocity distribution), one CSV row per setting with the measured and the predicted RMSE. A
// thin alias of the campaign engine (fss/campaign/results.h): a campaign of one image and one
// code, every setting with the same seeds, its rows written in the sweep's CSV form.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "command.h"
#include "fss/campaign/spec.h"
#include "simulation_flags.h"

namespace fssim {

class SweepCommand : public Command {
 public:
  // Adds the `sweep` subcommand to `parent`.
  explicit SweepCommand(CLI::App& parent);
  int Run() const override;

  // The swept values and the results, for --plot (NaN where a setting has none): the measured
  // value, its error bar (1.96 standard errors), the prediction, and whether the RMSE margin
  // is below 3B.
  struct Curves {
    std::vector<double> x, measured, error, predicted;
    std::vector<bool> open;
    std::vector<std::string> too_narrow;  // the swept values of the too-narrow settings
  };
  // The pictures of --plot: a PNG and the same figure as SVG.
  struct PlotPictures {
    std::vector<std::uint8_t> png;
    std::string svg;
  };

 private:
  // The swept values of --velocity and --snr, checked.
  struct Grid {
    std::vector<double> velocities;
    std::vector<double> snrs;
    bool by_velocity() const { return velocities.size() > 1; }
  };
  Grid ParseGrid() const;
  void CheckPaths() const;
  fss::ResolvedCampaign Campaign(const Grid& grid, const fss::ShutterCode& code,
                                 const fss::SimulationOptions& options) const;
  int Sweep() const;
  PlotPictures Plot(const Grid& grid, const fss::ShutterCode& code,
                    const fss::SimulationOptions& options, const Curves& c) const;
  // Where --plot's pictures go: the PNG (empty: none) and the SVG (empty: none).
  std::pair<std::string, std::string> PlotPaths() const;
  void WritePlot(const PlotPictures& pictures, const std::vector<std::string>& inputs,
                 std::FILE* console) const;

  SimulationFlags flags_;
  std::string input_;
  std::string velocity_ = "1";
  CLI::Option* velocity_option_ = nullptr;
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG (and SVG beside it) or SVG of the RMSE, or empty
};

}  // namespace fssim
