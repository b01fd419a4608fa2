// The main command, `fssim --input IMAGE ...`: simulates the observation of an
// image through a code, restores it, writes the outputs and prints the
// measured and predicted errors.
#pragma once

#include <string>

#include "cli_common.h"
#include "command.h"
#include "fss/io/outputs.h"
#include "simulation_flags.h"

namespace fssim {

class SimulateCommand : public Command {
 public:
  // Adds the command's options to `app` itself (not as a subcommand).
  explicit SimulateCommand(CLI::App& app);
  // Runs after a parse that selected no subcommand.
  int Run() const override;

 private:
  int Simulate(ErrorContext* context) const;

  SimulationFlags flags_;
  std::string input_;
  CLI::Option* input_option_ = nullptr;
  std::string outdir_ = "out";
  fss::OutputOptions output_options_;
  bool no_plots_ = false;
  std::string png_depth_ = "8";  // 8, 16 or auto
};

}  // namespace fssim
