// `fssim code generate | analyze | optimize`: shutter code design on the
// command line, over fss/design/. One class per command, each in its own file
// (code_generate.cpp, code_analyze.cpp, code_optimize.cpp); CodeCommands adds
// them under `code` and runs the one selected.
#pragma once

#include <string>

#include "command.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"

namespace fssim {

// `code generate FAMILY --length L ...`: writes a generated code.
class CodeGenerateCommand : public Command {
 public:
  explicit CodeGenerateCommand(CLI::App& code);
  int Run() const override;

 private:
  std::string family_;
  fss::GenerateOptions options_;
  std::string output_;
};

// `code analyze CODE ...`: the figures of merit of a code.
class CodeAnalyzeCommand : public Command {
 public:
  explicit CodeAnalyzeCommand(CLI::App& code);
  int Run() const override;

 private:
  std::string code_;
  double velocity_ = 1.0;
  double dt_ = 1.0;
  double snr_ = 100.0;
  std::string mode_ = "numerical";
  int grid_ = 0;
  std::string json_;
};

// `code optimize --length L --velocity V ...`: the best code of a length.
class CodeOptimizeCommand : public Command {
 public:
  explicit CodeOptimizeCommand(CLI::App& code);
  int Run() const override;

 private:
  void WriteCode(const fss::OptimizeOptions& options, const fss::OptimizationResult& result) const;

  fss::OptimizeOptions options_;
  std::string mode_ = "numerical";
  std::string output_;
};

class CodeCommands : public Command {
 public:
  // Adds the `code` subcommand, with its three subcommands, to `parent`.
  explicit CodeCommands(CLI::App& parent);
  // Runs the subcommand selected.
  int Run() const override;

 private:
  CodeGenerateCommand generate_;
  CodeAnalyzeCommand analyze_;
  CodeOptimizeCommand optimize_;
};

// Usage error unless 0 < |v| dt < 2, naming --velocity and --dt; `what` is
// what needs the band ("the sinc code", "the optimizer").
void check_design_band(double velocity, double dt, const std::string& what);

}  // namespace fssim
