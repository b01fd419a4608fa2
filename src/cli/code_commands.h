// `fssim code generate | analyze | optimize`: shutter code design on the
// command line, over fss/design.h.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"

namespace fssim {

class CodeCommands {
 public:
  // Adds the `code` subcommand, with its three subcommands, to `app`. The
  // object must outlive the parse: the options write into it.
  explicit CodeCommands(CLI::App& app);
  CodeCommands(const CodeCommands&) = delete;
  CodeCommands& operator=(const CodeCommands&) = delete;

  // True when the command line selected `code`.
  bool parsed() const;
  // Runs the selected command after a successful parse; returns the exit status.
  int Run() const;

 private:
  int RunGenerate() const;
  int RunAnalyze() const;
  int RunOptimize() const;

  CLI::App* code_ = nullptr;
  CLI::App* generate_ = nullptr;
  CLI::App* analyze_ = nullptr;
  CLI::App* optimize_ = nullptr;

  // generate
  std::string family_;
  fss::GenerateOptions generate_options_;
  std::string generate_output_;

  // analyze
  std::string analyze_code_;
  double analyze_velocity_ = 1.0;
  double analyze_dt_ = 1.0;
  double analyze_snr_ = 100.0;
  std::string analyze_mode_ = "numerical";
  int analyze_grid_ = 0;
  std::string analyze_json_;

  // optimize
  fss::OptimizeOptions optimize_options_;
  std::string optimize_mode_ = "numerical";
  std::string optimize_output_;
};

}  // namespace fssim
