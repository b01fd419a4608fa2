// The main command, `fssim --input IMAGE ...`: simulates the observation of an
// image through a code, restores it, writes the outputs and prints the
// measured and predicted errors.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "cli_common.h"
#include "fss/io/outputs.h"
#include "simulation_flags.h"

namespace fssim {

class SimulateCommand {
 public:
  // Adds the command's options to `app` itself (not as a subcommand); the
  // object must outlive the parse.
  explicit SimulateCommand(CLI::App& app);
  SimulateCommand(const SimulateCommand&) = delete;
  SimulateCommand& operator=(const SimulateCommand&) = delete;

  // Runs after a parse that selected no subcommand; returns the exit status.
  int Run() const;

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
