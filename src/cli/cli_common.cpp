#include "cli_common.h"

#include <unistd.h>
#include <charconv>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <new>

#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"
#include "io/safe_write.h"

namespace fssim {

namespace {

// A validator of a number: "value TEXT PROBLEM", PROBLEM being what
// `problem` says of the value ("" when it is acceptable). A text that is not
// a number is judged as NaN, which every rule here refuses.
CLI::Validator number_validator(const std::function<std::string(double)>& problem,
                                const std::string& description, const std::string& name) {
  return CLI::Validator(
      [problem](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) value = std::nan("");
        const std::string why = problem(value);
        return why.empty() ? why : "value " + text + " " + why;
      },
      description, name);
}

// A validator of an integer in [minimum, maximum]: "value TEXT must be RULE".
CLI::Validator integer_validator(long long minimum, long long maximum, const std::string& rule,
                                 const std::string& description) {
  return CLI::Validator(
      [minimum, maximum, rule](std::string& text) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < minimum || value > maximum) {
          return "value " + text + " must be " + rule;
        }
        return {};
      },
      description);
}

}  // namespace

CLI::Validator finite() {
  return number_validator(
      [](double value) { return std::isfinite(value) ? "" : "is not a finite number"; }, "FINITE",
      "finite");
}

CLI::Validator positive() {
  return number_validator([](double value) { return value > 0.0 ? "" : "must be > 0"; }, "POSITIVE",
                          "positive");
}

CLI::Validator scale() {
  return number_validator(
      [](double value) -> std::string {
        if (!std::isfinite(value)) return "is not a finite number";
        if (!fss::scale_is_positive(value)) return "must be > 0";
        const std::string rule = fss::scale_rule(value);
        return rule.empty() ? rule : "is out of range: it " + rule;
      },
      "POSITIVE", "positive");
}

CLI::Validator at_least(long long minimum) {
  return integer_validator(minimum, std::numeric_limits<long long>::max(),
                           "an integer >= " + std::to_string(minimum),
                           ">=" + std::to_string(minimum));
}

CLI::Validator integer_in(long long minimum, long long maximum) {
  const std::string interval = "[" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
  return integer_validator(minimum, maximum, "an integer in " + interval, interval);
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

CLI::Validator rmse_margin_value(bool allow_default) {
  const long long lowest = allow_default ? fss::kRmseMarginDefault : 0;
  const std::string rule = "auto or an integer in [" + std::to_string(lowest) + ", " +
                           std::to_string(fss::kMaxMarginColumns) + "]";
  return CLI::Validator(
      [lowest, rule](std::string& text) -> std::string {
        if (text == "auto") {
          text = std::to_string(fss::kRmseMarginAuto);
          return {};
        }
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < lowest ||
            value > fss::kMaxMarginColumns) {
          return "value " + text + " must be " + rule;
        }
        return {};
      },
      "auto|COLUMNS", "rmse margin");
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

namespace {

// Length of the well-formed UTF-8 sequence at text[i] (1 for ASCII), 0 if
// there is none.
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  if (lead < 0x80) return 1;
  const std::size_t length = lead >= 0xC2 && lead <= 0xDF   ? 2
                             : lead >= 0xE0 && lead <= 0xEF ? 3
                             : lead >= 0xF0 && lead <= 0xF4 ? 4
                                                            : 0;
  if (length == 0 || i + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
  }
  // Overlong forms, surrogates and values past U+10FFFF.
  if (lead == 0xE0 && byte(i + 1) < 0xA0) return 0;
  if (lead == 0xED && byte(i + 1) >= 0xA0) return 0;
  if (lead == 0xF0 && byte(i + 1) < 0x90) return 0;
  if (lead == 0xF4 && byte(i + 1) >= 0x90) return 0;
  return length;
}

// `text` with bytes that are not UTF-8 and the invisible U+FEFF (a byte
// order mark) written as \xNN, so a message shows what the file holds.
std::string escape_invisible_and_invalid(std::string_view text) {
  constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    std::size_t length = utf8_length(text, i);
    const bool bom = text.substr(i, 3) == "\xEF\xBB\xBF";
    if (length == 0 || bom) {
      for (std::size_t k = 0; k < (bom ? 3 : 1); ++k) {
        const auto byte = static_cast<unsigned char>(text[i + k]);
        out += "\\x";
        out += kHex[byte >> 4];
        out += kHex[byte & 0xf];
      }
      i += bom ? 3 : 1;
      continue;
    }
    out.append(text.substr(i, length));
    i += length;
  }
  return out;
}

}  // namespace

void report_error(std::string_view message) {
  fss::write_stderr("fssim: error: " +
                    escape_invisible_and_invalid(fss::escape_control_characters(message)) + "\n");
}

void write_output(const std::string& path, std::string_view bytes,
                  const std::vector<std::string>& inputs) {
  if (!is_stdout(path)) {
    fss::write_file_in_folders(path, bytes, inputs);
    return;
  }
  std::cout.flush();
  if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() ||
      std::fflush(stdout) != 0) {
    fss::throw_runtime_error(std::string("cannot write to standard output: ") +
                             std::strerror(errno));
  }
}

int check_standard_streams(int status) {
  errno = 0;
  std::cout.flush();
  bool out_failed = !std::cout.good();
  if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) out_failed = true;
  const int out_error = errno;
  // close() reports what a buffered write could not (NFS, a full disk).
  if (::close(STDOUT_FILENO) != 0 && errno != EBADF) out_failed = true;
  if (out_failed && status == kExitSuccess) {  // else the failure is reported already
    report_error(std::string("cannot write to standard output: ") +
                 std::strerror(out_error != 0 ? out_error : EIO));
  }
  std::cerr.flush();
  const bool err_failed = !std::cerr.good() || std::fflush(stderr) != 0 || std::ferror(stderr) != 0;
  return (out_failed || err_failed) && status == kExitSuccess ? kExitRuntime : status;
}

void check_adc_gain(bool adc_gain_given, int adc_bits) {
  if (adc_gain_given && adc_bits == 0) {
    fss::throw_usage_error("--adc-gain: needs --adc-bits (without an ADC there are no counts)");
  }
}

void check_sensor_options(const fss::SensorModel& sensor) {
  std::string error;
  if (sensor.IsValid(&error)) return;
  // "read_noise_electrons = -1: must be ..." -> "--read-noise: value -1 must be ..."
  static const std::pair<const char*, const char*> kOptions[] = {
      {"read_noise_electrons", "--read-noise"},
      {"dark_current_electrons_per_slot", "--dark-current"},
      {"full_well_electrons", "--full-well"},
      {"adc_bits", "--adc-bits"},
      {"adc_gain_electrons_per_count", "--adc-gain"}};
  const std::size_t equals = error.find(" = ");
  const std::size_t colon = error.find(": ", equals);
  if (equals == std::string::npos || colon == std::string::npos) fss::throw_usage_error(error);
  const std::string field = error.substr(0, equals);
  std::string option = field;
  for (const auto& [name, flag] : kOptions) {
    if (field == name) option = flag;
  }
  fss::throw_usage_error(option + ": value " + error.substr(equals + 3, colon - equals - 3) + " " +
                         error.substr(colon + 2));
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
