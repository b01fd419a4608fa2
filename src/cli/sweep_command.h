// `fssim sweep`: the simulator over a grid of velocities and snr values, one
// CSV row per setting with the measured and the predicted RMSE. A thin alias
// of the campaign engine (fss/campaign/results.h): a campaign of one image
// and one code, every setting with the same seeds, its rows written in the
// sweep's CSV form.
#pragma once

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

  SimulationFlags flags_;
  std::string input_;
  std::string velocity_ = "1";
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG of measured and predicted RMSE, or empty
};

}  // namespace fssim
