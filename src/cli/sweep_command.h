// `fssim sweep`: the simulator over a grid of velocities and snr values, one
// CSV row per setting with the measured and the predicted RMSE.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "fss/pipeline/simulate.h"

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
  int RunSweep() const;

  CLI::App* sweep_ = nullptr;
  std::string input_;
  std::string code_name_ = "raskar";
  std::string mode_ = "numerical";
  std::string velocity_ = "1";
  std::string snr_ = "100";
  std::string output_;
  std::string plot_;  // --plot: PNG of measured and predicted RMSE, or empty
  fss::SimulationOptions options_;
};

}  // namespace fssim
