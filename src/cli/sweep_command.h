// `fssim sweep`: the simulator over a grid of velocities and snr values, one
// CSV row per setting with the measured and the predicted RMSE.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

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
