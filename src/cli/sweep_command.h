// `fssim sweep`: the simulator over a grid of velocities and snr values, one
// CSV row per setting with the measured and the predicted RMSE.
#pragma once

#include <string>
#include <vector>

#include "command.h"
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
  int Sweep() const;

  SimulationFlags flags_;
  std::string input_;
  std::string velocity_ = "1";
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG of measured and predicted RMSE, or empty
};

}  // namespace fssim
