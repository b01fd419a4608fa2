// `fssim sweep`: the simulator over a grid of velocities and snr values, one
// CSV row per setting with the measured and the predicted RMSE. A thin alias
// of the campaign engine (fss/campaign/results.h): a campaign of one image
// and one code, every setting with the same seeds, its rows written in the
// sweep's CSV form.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "fss/campaign/spec.h"
#include "simulation_flags.h"

namespace fssim {

class SweepCommand {
 public:
  // Adds the `sweep` subcommand to `app`; the object must outlive the parse.
  explicit SweepCommand(CLI::App& app);
  SweepCommand(const SweepCommand&) = delete;
  SweepCommand& operator=(const SweepCommand&) = delete;

  bool parsed() const;
  // Runs the sweep after a successful parse; returns the exit status.
  int Run() const;

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

  CLI::App* sweep_ = nullptr;
  SimulationFlags flags_;
  std::string input_;
  std::string velocity_ = "1";
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG of measured and predicted RMSE, or empty
};

}  // namespace fssim
