#include "cli_common.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <new>

#include "fss/core/error.h"

namespace fssim {

CLI::Validator finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) {
          return "value " + text + " is not a finite number";
        }
        return {};
      },
      "FINITE", "finite");
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0)) {
          return "value " + text + " must be > 0";
        }
        return {};
      },
      "POSITIVE", "positive");
}

CLI::Validator at_least(long long minimum) {
  return CLI::Validator(
      [minimum](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < minimum) {
          return "value " + text + " must be an integer >= " + std::to_string(minimum);
        }
        return {};
      },
      ">=" + std::to_string(minimum));
}

std::string help_hint(const CLI::App& app) {
  std::string command = app.get_name();
  const CLI::App* current = &app;
  while (current != nullptr) {
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : current->get_subcommands()) {
      next = sub;
      command += " " + sub->get_name();
      break;
    }
    current = next;
  }
  return command + " --help";
}

std::string first_given_option(const CLI::App& app) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0) continue;
    const std::string name = option->get_name();
    if (name == "--help" || name == "--version") continue;
    return name;
  }
  return {};
}

int run_reporting_errors(const std::function<int()>& body) {
  try {
    return body();
  } catch (const fss::Error& e) {
    std::cerr << "fssim: error: " << fss::escape_control_characters(e.what()) << "\n";
    return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
  } catch (const std::bad_alloc&) {
    std::cerr << "fssim: error: out of memory\n";
    return kExitRuntime;
  } catch (const std::exception& e) {
    std::cerr << "fssim: error: " << e.what() << "\n";
    return kExitRuntime;
  }
}

}  // namespace fssim
