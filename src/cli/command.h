// The base of every fssim command: the CLI11 app its options are bound to,
// whether the command line selected it, and running it.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace fssim {

class Command {
 public:
  Command(const Command&) = delete;
  Command& operator=(const Command&) = delete;
  virtual ~Command() = default;

  // True when the command line selected this command.
  bool parsed() const { return app_->parsed(); }
  // Runs the command after a successful parse; returns the exit status.
  virtual int Run() const = 0;

 protected:
  // `app`: the command's own CLI11 app (a subcommand, or the main app). The
  // options a derived class binds write into it, so the command must outlive
  // the parse.
  explicit Command(CLI::App& app) : app_(&app) {}
  // Adds the command to `parent` as its subcommand `name`.
  Command(CLI::App& parent, const std::string& name, const std::string& description)
      : Command(*parent.add_subcommand(name, description)) {}
  CLI::App& app() const { return *app_; }

 private:
  CLI::App* app_;
};

}  // namespace fssim
