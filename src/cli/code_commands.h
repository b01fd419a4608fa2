// `fssim code generate | analyze | optimize`: shutter code design on the
// command line, over fss/design/. One class per command, each in its own file
// (code_generate.cpp, code_analyze.cpp, code_optimize.cpp); CodeCommands adds
// them under `code` and runs the one selected.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "command.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/model/velocity_distribution.h"

namespace fssim {

// The sensor options of `code analyze` and `code optimize` (docs/method.md
// §10): --read-noise, --dark-current, --adc-bits, --adc-gain, and --full-well,
// which is refused (the figure of merit is linear in the charge).
class SensorFlags {
 public:
  void Add(CLI::App* app);
  // The sensor asked for; a usage error naming the option when a value is
  // out of range (SensorModel::IsValid), --adc-gain comes without
  // --adc-bits, or --full-well is given.
  fss::SensorModel Model(const std::string& command) const;

 private:
  double read_noise_ = 0.0;
  double dark_current_ = 0.0;
  int adc_bits_ = 0;
  std::optional<double> adc_gain_;
  std::optional<double> full_well_;
};

// The restoration options of `code analyze` and `code optimize` (docs/method.md
// §12): --restoration, --prior (wiener only) and --regularization (tikhonov
// only).
class RestorationFlags {
 public:
  void Add(CLI::App* app);
  // The restoration asked for; a usage error naming the option when --prior
  // or --regularization is given for a method that does not take it, the
  // prior is the oracle (code design has no image) or a value is out of range.
  fss::RestorationOptions Options() const;

 private:
  std::string method_ = "inverse";
  std::string prior_;
  std::string regularization_ = "optimal";
  CLI::Option* prior_option_ = nullptr;
  CLI::Option* regularization_option_ = nullptr;
};

// `code generate FAMILY --length L ...`: writes a generated code.
class CodeGenerateCommand : public Command {
 public:
  explicit CodeGenerateCommand(CLI::App& code);
  int Run() const override;

 private:
  // Refuses an option the family does not use (--velocity, --dt: sinc and
  // mip; --seed, --analog: random).
  void CheckFamilyOptions(fss::CodeFamily family) const;

  std::string family_;
  fss::GenerateOptions options_;
  std::string output_;
  CLI::Option* velocity_option_ = nullptr;
  CLI::Option* dt_option_ = nullptr;
  CLI::Option* seed_option_ = nullptr;
  CLI::Option* analog_option_ = nullptr;
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
  SensorFlags sensor_;
  RestorationFlags restoration_;
  std::string json_;
  std::string velocity_distribution_;
  CLI::Option* velocity_option_ = nullptr;
  CLI::Option* velocity_distribution_option_ = nullptr;
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
  SensorFlags sensor_;
  RestorationFlags restoration_;
  std::string output_;
  std::string velocity_distribution_;
  CLI::Option* velocity_option_ = nullptr;
  CLI::Option* velocity_distribution_option_ = nullptr;
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

// --velocity-distribution SPEC of code analyze and optimize (docs/method.md §13).
void add_velocity_distribution_option(CLI::App* app, std::string* spec, CLI::Option** option);
// The distribution asked for (none without the option): a usage error when --velocity is given
// too, the spec is neither a distribution nor a file (load_velocity_distribution), or the
// support reaches |v| dt >= 2; a runtime one when the file cannot be read.
std::optional<fss::VelocityDistribution> design_velocity_distribution(
    const CLI::Option* option, const std::string& spec, const CLI::Option* velocity_option,
    double dt);

}  // namespace fssim
