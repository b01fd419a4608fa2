// `fssim sweep`: the simulator over a grid of velocities and snr values (or of snr values under
// a velocity distribution), one CSV row per setting with the measured and the predicted RMSE. A
// thin alias of the campaign engine (fss/campaign/results.h): a campaign of one image and one
// code, every setting with the same seeds, its rows written in the sweep's CSV form.
#pragma once

#include <cstdint>
#include <string>
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

  // The swept values and the results, for --plot (NaN where a setting has none).
  struct Curves {
    std::vector<double> x, measured, predicted;
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
  std::vector<std::uint8_t> Plot(const Grid& grid, const fss::ShutterCode& code,
                                 const fss::SimulationOptions& options, const Curves& c) const;

  SimulationFlags flags_;
  std::string input_;
  std::string velocity_ = "1";
  CLI::Option* velocity_option_ = nullptr;
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG of measured and predicted RMSE, or empty
};

}  // namespace fssim
