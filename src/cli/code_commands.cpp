#include "code_commands.h"

#include <cmath>

#include "cli_common.h"
#include "fss/core/error.h"

namespace fssim {

namespace {

CLI::App& add_code_command(CLI::App& app) {
  CLI::App* code = app.add_subcommand("code", "design shutter codes: generate, analyze, optimize");
  // At most one; none is reported in Run(), so that an unknown word after
  // `code` is named in the error instead of "a subcommand is required".
  code->require_subcommand(0, 1);
  return *code;
}

}  // namespace

void check_design_band(double velocity, double dt, const std::string& what) {
  if (!fss::design_band_is_valid(velocity, dt)) {
    fss::throw_usage_error("--velocity " + format_exact(velocity) + " with --dt " +
                           format_exact(dt) + ": " + what +
                           " needs 0 < |velocity| dt < 2, got |velocity| dt = " +
                           format_exact(std::abs(velocity) * dt));
  }
}

CodeCommands::CodeCommands(CLI::App& app)
    : code_(&add_code_command(app)), generate_(*code_), analyze_(*code_), optimize_(*code_) {}

bool CodeCommands::parsed() const { return code_->parsed(); }

int CodeCommands::Run() const {
  return run_reporting_errors([this] {
    if (generate_.parsed()) return generate_.Run();
    if (analyze_.parsed()) return analyze_.Run();
    if (optimize_.parsed()) return optimize_.Run();
    fss::throw_usage_error(
        "code needs a subcommand: generate, analyze or optimize (see fssim code --help)");
  });
}

}  // namespace fssim
