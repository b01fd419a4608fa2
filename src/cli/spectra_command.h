// `fssim spectra --output FILE CODE...`: |K| of several codes on one plot, no
// simulation.
#pragma once

#include <string>
#include <vector>

#include "command.h"
#include "fss/io/plot.h"

namespace fssim {

class SpectraCommand : public Command {
 public:
  // Adds the `spectra` subcommand to `parent`.
  explicit SpectraCommand(CLI::App& parent);
  int Run() const override;

 private:
  int Plot() const;

  std::vector<std::string> codes_;
  double velocity_ = 1.0;
  double dt_ = 1.0;
  bool linear_ = false;
  std::string output_;
  fss::PlotOptions plot_{800, 420, ""};
};

}  // namespace fssim
