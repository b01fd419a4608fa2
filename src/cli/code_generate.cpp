// `fssim code generate`.
#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "code_commands.h"
#include "fss/core/error.h"
#include "fss/model/code.h"

namespace fssim {

namespace {

const char kFamilies[] = "sinc, mip, random, snapshot, accumulation";

std::string gain_domain(const fss::GenerateOptions& options) {
  return options.analog ? "[0, 1)" : "[-1, 1)";
}

// The comment line that opens a generated code file.
std::string generate_header(const fss::GenerateOptions& o) {
  const std::string family = fss::to_string(o.family);
  std::string text = "# " + family + " code, L = " + std::to_string(o.length);
  std::string command = "fssim code generate " + family + " --length " + std::to_string(o.length);
  if (o.family == fss::CodeFamily::kSinc || o.family == fss::CodeFamily::kMip) {
    text += ", designed for velocity " + format_number(o.velocity_px_per_slot) + ", dt " +
            format_number(o.dt);
    command +=
        " --velocity " + format_number(o.velocity_px_per_slot) + " --dt " + format_number(o.dt);
  } else if (o.family == fss::CodeFamily::kRandom) {
    text += ", gains uniform on " + gain_domain(o) + ", seed " + std::to_string(o.seed);
    command += " --seed " + std::to_string(o.seed) + (o.analog ? " --analog" : "");
  }
  return text + " (" + command + ")\n";
}

}  // namespace

CodeGenerateCommand::CodeGenerateCommand(CLI::App& code)
    : Command(code, "generate",
              "write a code: sinc, mip (the paper's constructions for |v| dt), "
              "random, snapshot or accumulation") {
  CLI::App& generate = app();
  generate.add_option("FAMILY", family_, std::string("code family: ") + kFamilies)
      ->required()
      ->check(CLI::IsMember({"sinc", "mip", "random", "snapshot", "accumulation"}));
  generate.add_option("-L,--length", options_.length, "number of gains L")
      ->required()
      ->check(at_least(1));
  velocity_option_ =
      generate
          .add_option("-v,--velocity", options_.velocity_px_per_slot,
                      "sinc, mip: velocity the code is designed for (pixels per slot)")
          ->check(finite())
          ->capture_default_str();
  dt_option_ = generate.add_option("--dt", options_.dt, "sinc, mip: time slot length, > 0")
                   ->check(scale())
                   ->capture_default_str();
  seed_option_ = generate.add_option("--seed", options_.seed, "random: seed of the gains")
                     ->check(seed_value())
                     ->capture_default_str();
  analog_option_ = generate.add_flag("--analog", options_.analog,
                                     "random: gains on [0, 1) (analog) instead of [-1, 1)");
  generate.add_option("-o,--output", output_,
                      "code file to write (default, or -: standard output)");
}

void CodeGenerateCommand::CheckFamilyOptions(fss::CodeFamily family) const {
  const bool designed = family == fss::CodeFamily::kSinc || family == fss::CodeFamily::kMip;
  const bool random = family == fss::CodeFamily::kRandom;
  for (const auto& [option, used] : {std::pair{velocity_option_, designed},
                                     {dt_option_, designed},
                                     {seed_option_, random},
                                     {analog_option_, random}}) {
    if (option->count() > 0 && !used) {
      fss::throw_usage_error(option->get_name() + ": the " + family_ +
                             " code does not use it (--velocity and --dt are for sinc and mip, "
                             "--seed and --analog for random)");
    }
  }
}

int CodeGenerateCommand::Run() const {
  fss::GenerateOptions options = options_;
  options.family = *fss::code_family_from_string(family_);
  CheckFamilyOptions(options.family);
  if (options.family == fss::CodeFamily::kSinc || options.family == fss::CodeFamily::kMip) {
    check_design_band(options.velocity_px_per_slot, options.dt, "the " + family_ + " code");
  }
  if (options.length > fss::kMaxGeneratedCodeLength) {
    fss::throw_usage_error("--length " + std::to_string(options.length) + ": at most " +
                           std::to_string(fss::kMaxGeneratedCodeLength) + " gains");
  }
  const fss::ShutterCode code = fss::generate_code(options);
  const std::string text = generate_header(options) + fss::format_code_txt(code);
  if (output_.empty() || is_stdout(output_)) {
    write_output("-", text);
  } else {
    write_output(output_, text);
    std::printf("%s code, L = %d: written to %s\n", family_.c_str(), options.length,
                output_.c_str());
  }
  return kExitSuccess;
}

}  // namespace fssim
