#include "cli_common.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <new>

#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"

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

CLI::Validator scale() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) {
          return "value " + text + " is not a finite number";
        }
        if (!fss::scale_is_positive(value)) return "value " + text + " must be > 0";
        if (const std::string rule = fss::scale_rule(value); !rule.empty()) {
          return "value " + text + " is out of range: it " + rule;
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

CLI::Validator integer_in(long long minimum, long long maximum) {
  return CLI::Validator(
      [minimum, maximum](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < minimum || value > maximum) {
          return "value " + text + " must be an integer in [" + std::to_string(minimum) + ", " +
                 std::to_string(maximum) + "]";
        }
        return {};
      },
      "[" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]");
}

CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec != std::errc() || ptr != end) {
          return "value " + text + " must be an integer in [0, " +
                 std::to_string(std::numeric_limits<std::uint64_t>::max()) + "]";
        }
        return {};
      },
      "UINT64", "seed");
}

CLI::Validator not_empty() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return text.empty() ? std::string("the path must not be empty") : std::string();
      },
      "PATH", "not empty");
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
    std::string name = option->get_name();
    if (name == "--help" || name == "--version") continue;
    return name;
  }
  return {};
}

void report_error(std::string_view message) {
  std::cerr << "fssim: error: " << fss::escape_control_characters(message) << std::endl;
}

int run_reporting_errors(const std::function<int()>& body, const ErrorContext* context) {
  const ErrorContext none;
  const ErrorContext& c = context != nullptr ? *context : none;
  try {
    return body();
  } catch (const fss::Error& e) {
    report_error(std::string(e.what()) + (e.kind() == fss::ErrorKind::kLimit ? c.limit_hint : ""));
    return e.kind() == fss::ErrorKind::kUsage ? kExitUsage : kExitRuntime;
  } catch (const std::bad_alloc&) {
    report_error("out of memory" + (c.activity.empty() ? "" : " while " + c.activity));
    return kExitRuntime;
  } catch (const std::exception& e) {
    report_error(std::string(e.what()) + (c.activity.empty() ? "" : " (while " + c.activity + ")"));
    return kExitRuntime;
  }
}

}  // namespace fssim
