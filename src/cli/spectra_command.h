// `fssim spectra --output FILE CODE...`: |K| of several codes on one plot, no
// simulation.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "fss/io/plot.h"

namespace fssim {

class SpectraCommand {
 public:
  // Adds the `spectra` subcommand to `app`; the object must outlive the parse.
  explicit SpectraCommand(CLI::App& app);
  SpectraCommand(const SpectraCommand&) = delete;
  SpectraCommand& operator=(const SpectraCommand&) = delete;

  bool parsed() const;
  // Runs the command after a successful parse; returns the exit status.
  int Run() const;

 private:
  int Plot() const;

  CLI::App* spectra_ = nullptr;
  std::vector<std::string> codes_;
  double velocity_ = 1.0;
  double dt_ = 1.0;
  bool linear_ = false;
  std::string output_;
  fss::PlotOptions plot_{800, 420, ""};
};

}  // namespace fssim
