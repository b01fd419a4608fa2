// fssim: the command line over the fss library. main() parses the command
// line and hands it to the command it selects: the simulation itself
// (simulate_command.cpp), spectra, code generate / analyze / optimize, sweep, campaign.
#include <CLI/CLI.hpp>
#include <csignal>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "campaign_command.h"
#include "cli_common.h"
#include "code_commands.h"
#include "simulate_command.h"
#include "spectra_command.h"
#include "sweep_command.h"

namespace {

// CLI11's message for `e` in fssim's words: "unexpected arguments: 3 -x" (in
// the order typed), "--velocity needs a value".
std::string parse_error_message(const CLI::App& app, const CLI::ParseError& e) {
  std::string what = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    std::string extras;
    for (const std::string& word : app.remaining(true))
      extras += (extras.empty() ? "" : " ") + word;
    if (!extras.empty()) return "unexpected arguments: " + extras;
  }
  // "--velocity: 1 required FLOAT:FINITE missing"
  const std::size_t colon = what.find(": ");
  if (colon != std::string::npos && what.find(" required ", colon) != std::string::npos &&
      what.size() > 8 && what.compare(what.size() - 8, 8, " missing") == 0) {
    return what.substr(0, colon) + " needs a value";
  }
  return what;
}

// --help shows a value's kind in one plain word (NUMBER, INTEGER, SEED,
// PATH, TEXT), not CLI11's type and validator strings such as
// "FLOAT:(FINITE) AND (POSITIVE)": the description says the rule.
void simplify_type_names(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string full = option->get_type_name();
    if (full.empty()) continue;
    const std::string type = full.substr(0, full.find(':'));
    std::string word = "TEXT";
    if (type.rfind("FLOAT", 0) == 0) word = "NUMBER";
    if (type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0) word = "INTEGER";
    if (full.find("UINT64") != std::string::npos) word = "SEED";
    if (full.find("PATH") != std::string::npos) word = "PATH";
    option->type_name(word);
    // Validators' names go too, but a list of choices ("{numerical,analog}") stays.
    for (int i = 0;; ++i) {
      CLI::Validator* validator = nullptr;
      try {
        validator = option->get_validator(i);
      } catch (const CLI::OptionNotFound&) {
        break;
      }
      if (validator->get_description().rfind('{', 0) != 0) validator->description("");
    }
  }
  for (CLI::App* sub : app.get_subcommands({})) simplify_type_names(*sub);
}

// Whether the command line asks for help (of fssim or of a subcommand).
bool asks_for_help(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--") break;
    if (arg == "-h" || arg == "--help") return true;
  }
  return false;
}

// Parses the command line; an error is reported and its exit status returned.
int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    fssim::report_error(parse_error_message(app, e) + " (see " + fssim::help_hint(app) + ")");
    return fssim::kExitUsage;
  } catch (const std::exception& e) {
    fssim::report_error(std::string(e.what()) + " (see fssim --help)");
    return fssim::kExitUsage;
  }
  return -1;
}

int run(int argc, char** argv) {
  CLI::App app{
      "fssim: flutter shutter camera simulator (Tendero, IPOL 2012). Simulates the motion-blurred, "
      "photon-noisy observation of an image through a flutter shutter code, restores it by "
      "inverse filtering, and measures and predicts the error.",
      "fssim"};
  app.set_version_flag("--version", std::string("fssim ") + FSS_VERSION);
  app.get_formatter()->column_width(32);
  const fssim::SimulateCommand simulate(app);
  app.require_subcommand(0, 1);
  const fssim::SpectraCommand spectra(app);
  const fssim::CodeCommands code(app);
  const fssim::SweepCommand sweep(app);
  const fssim::CampaignCommand campaign(app);

  // Only --help shows the type names (and renaming them costs an exception per option).
  if (asks_for_help(argc, argv)) simplify_type_names(app);
  if (const int status = parse(app, argc, argv); status >= 0) return status;
  if (app.get_subcommands().empty()) return simulate.Run();
  if (const std::string option = fssim::first_given_option(app); !option.empty()) {
    fssim::report_error(option + " is an option of the simulation, not of '" +
                        app.get_subcommands().front()->get_name() +
                        "'; put the subcommand's options after its name (see " +
                        fssim::help_hint(app) + ")");
    return fssim::kExitUsage;
  }
  if (spectra.parsed()) return spectra.Run();
  if (code.parsed()) return code.Run();
  if (campaign.parsed()) return campaign.Run();
  return sweep.Run();
}

}  // namespace

int main(int argc, char** argv) {
  // Beyond a file size limit (ulimit -f), a write must fail with EFBIG, which
  // is reported and cleaned up, rather than kill the process mid-write.
  std::signal(SIGXFSZ, SIG_IGN);
  int status = fssim::kExitRuntime;
  try {
    status = run(argc, argv);
  } catch (const std::bad_alloc&) {
    fssim::report_error("out of memory");
  } catch (const std::exception& e) {
    fssim::report_error(e.what());
  } catch (...) {
    fssim::report_error("unexpected failure");
  }
  // Results that did not reach stdout (a full disk, /dev/full) are a failure.
  return fssim::check_standard_streams(status);
}
