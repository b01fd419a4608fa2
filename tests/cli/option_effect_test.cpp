// Every option of every command is honoured or refused, never accepted and
// ignored. The options are read from each command's own --help, so that a
// new option fails this test until its expected effect is declared here:
// - changes: the command's results (standard output and every file it
//   writes) differ from the same command without the option;
// - refused: exit 1 or 2 with one line on stderr (an option that does not
//   apply to this command or to the rest of its arguments);
// - same: the results are byte-identical (--threads, --max-memory and the
//   progress options, which must not change any result);
// - path: the option names an input or an output (output_paths_test.cpp),
//   or prints something else (--version).
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;

enum class Effect { kChanges, kRefused, kSame, kPath };

struct OptionCase {
  std::string option;     // its long name, as --help lists it
  std::string arguments;  // added to the command (a value; a prerequisite first)
  Effect effect;
  std::string reference = "";  // added to the command it is compared with
};

struct CommandCase {
  std::string command;  // the subcommand as typed ("" for the simulator)
  std::string base;     // its arguments: {IN} is the input image, {W} the output folder
  std::vector<OptionCase> options;
  bool verdicts = false;  // exit 1 is a verdict (campaign check), not a failure
};

// The long option names --help lists for `command`.
std::set<std::string> help_options(const std::string& command) {
  const CommandResult r = test::run_fssim(command + " --help");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::set<std::string> names;
  const std::regex option(R"(^\s+(-\w,)?(--[A-Za-z0-9-]+))");
  for (const std::string& line : test::lines_of(r.out)) {
    if (line.find("Subcommands:") != std::string::npos) break;
    std::smatch m;
    if (std::regex_search(line, m, option)) names.insert(m[2]);
  }
  return names;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
    text.replace(at, from.size(), to);
    at += to.size();
  }
  return text;
}

// `arguments` with the option of `o` added, or its value replaced where
// `arguments` already gives it.
std::string with_option(const std::string& arguments, const OptionCase& o) {
  const std::regex given("(^| )" + o.option + " [^ ]+");
  if (std::regex_search(arguments, given)) {
    return std::regex_replace(arguments, given, " " + o.arguments);
  }
  return arguments + " " + o.arguments;
}

// What a run shows: its exit status, its standard output and every file it
// wrote into the output folder (relative name -> bytes).
struct Results {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::map<std::string, std::string> files;
};

class OptionEffect : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(900, 8, 1));
    test::write_file(input_, std::string(png.begin(), png.end()));
  }

  Results run(const std::string& command, const std::string& arguments) const {
    fs::remove_all(out_);
    fs::create_directories(out_);
    const std::string line =
        replace_all(replace_all(arguments, "{IN}", quote(input_)), "{W}", quote(out_));
    const CommandResult r = test::run_fssim(command + " " + line);
    Results results{r.exit_code, r.out, r.err, {}};
    for (const auto& entry : fs::recursive_directory_iterator(out_)) {
      if (entry.is_regular_file()) {
        results.files[fs::relative(entry.path(), out_).string()] = test::read_file(entry.path());
      }
    }
    return results;
  }

  // Checks every option of `c` against its declared effect.
  void check(const CommandCase& c) const {
    const std::set<std::string> listed = help_options(c.command);
    std::set<std::string> declared = {"--help"};
    for (const OptionCase& o : c.options) declared.insert(o.option);
    EXPECT_EQ(listed, declared) << "fssim " << c.command
                                << ": declare the effect of each option --help lists";
    std::map<std::string, Results> references;  // each reference command runs once
    for (const OptionCase& o : c.options) {
      if (o.effect == Effect::kPath) continue;
      const std::string what = "fssim " + c.command + " " + o.arguments;
      const std::string reference = c.base + " " + o.reference;
      if (!references.contains(reference)) references[reference] = run(c.command, reference);
      const Results& before = references[reference];
      const int worst = c.verdicts ? 1 : 0;
      ASSERT_LE(before.exit_code, worst) << what << ": the reference run failed: " << before.err;
      const Results after = run(c.command, with_option(reference, o));
      if (o.effect == Effect::kRefused) {
        EXPECT_TRUE(after.exit_code == 1 || after.exit_code == 2) << what << ": not refused";
        EXPECT_EQ(test::lines_of(after.err).size(), 1u) << what << ": " << after.err;
        continue;
      }
      ASSERT_TRUE(after.exit_code >= 0 && after.exit_code <= worst) << what << ": " << after.err;
      const bool same = before.exit_code == after.exit_code && before.out == after.out &&
                        before.files == after.files;
      if (o.effect == Effect::kChanges) EXPECT_FALSE(same) << what << ": accepted and ignored";
      if (o.effect == Effect::kSame) EXPECT_TRUE(same) << what << ": must not change results";
    }
  }

  test::TempDir dir_;
  fs::path input_ = dir_ / "in.png";
  fs::path out_ = dir_ / "w";
};

// The sensor options, as the simulator and sweep take them: a read noise, a
// dark current, a full well the image's bright pixels reach at snr 100, an
// ADC, and its gain (which needs the ADC).
std::vector<OptionCase> sensor_cases() {
  return {{"--read-noise", "--read-noise 50", Effect::kChanges},
          {"--dark-current", "--dark-current 20", Effect::kChanges},
          {"--full-well", "--full-well 15000", Effect::kChanges},
          {"--adc-bits", "--adc-bits 10", Effect::kChanges},
          {"--adc-gain", "--adc-gain 30", Effect::kChanges, "--adc-bits 12"}};
}

// The options of one simulation, as the simulator and sweep take them, the
// sensor's included.
std::vector<OptionCase> simulation_cases() {
  std::vector<OptionCase> cases = {
      {"--code", "--code snapshot", Effect::kChanges},
      {"--mode", "--mode analog", Effect::kChanges},
      {"--velocity", "--velocity 1.5", Effect::kChanges},
      {"--velocity-distribution", "--velocity-distribution uniform:0.8:1.2", Effect::kChanges},
      {"--dt", "--dt 0.5", Effect::kChanges},
      {"--snr", "--snr 20", Effect::kChanges},
      {"--seed", "--seed 7", Effect::kChanges},
      {"--noise", "--noise aggregated", Effect::kChanges},
      {"--rmse-margin", "--rmse-margin 100", Effect::kChanges},
      {"--trials", "--trials 2", Effect::kChanges},
      {"--threads", "--threads 1", Effect::kSame},
      {"--max-memory", "--max-memory 2G", Effect::kSame},
      {"--restoration", "--restoration wiener", Effect::kChanges},
      // A lambda for Tikhonov, a prior for Wiener: compared with their defaults.
      {"--regularization", "--regularization 0.01", Effect::kChanges, "--restoration tikhonov"},
      {"--prior", "--prior oracle", Effect::kChanges, "--restoration wiener"}};
  for (const OptionCase& s : sensor_cases()) cases.push_back(s);
  return cases;
}

TEST_F(OptionEffect, Simulator) {
  CommandCase c{"", "-i {IN} -o {W}/out", simulation_cases()};
  const std::vector<OptionCase> own = {
      {"--version", "", Effect::kPath},  // prints the version, nothing else
      {"--input", "", Effect::kPath},
      {"--outdir", "", Effect::kPath},
      {"--restore-velocity", "--restore-velocity 1.1", Effect::kChanges},
      {"--no-plots", "--no-plots", Effect::kChanges},
      {"--sheet", "--sheet", Effect::kChanges},
      {"--report", "--report", Effect::kChanges},
      {"--save-float", "--save-float", Effect::kChanges},
      {"--png-depth", "--png-depth 16", Effect::kChanges}};
  c.options.insert(c.options.end(), own.begin(), own.end());
  check(c);
}

TEST_F(OptionEffect, Sweep) {
  CommandCase c{"sweep", "-i {IN} -o {W}/sweep.csv", simulation_cases()};
  const std::vector<OptionCase> own = {
      {"--input", "", Effect::kPath},
      {"--output", "", Effect::kPath},
      {"--plot", "--plot {W}/sweep.png", Effect::kChanges, "--velocity 1:2:1"}};
  c.options.insert(c.options.end(), own.begin(), own.end());
  check(c);
}

TEST_F(OptionEffect, Spectra) {
  check({"spectra",
         "raskar snapshot -o {W}/spectra.png",
         {{"--output", "", Effect::kPath},
          {"--velocity", "--velocity 1.5", Effect::kChanges},
          {"--dt", "--dt 0.5", Effect::kChanges},
          {"--linear", "--linear", Effect::kChanges},
          {"--width", "--width 600", Effect::kChanges},
          {"--height", "--height 300", Effect::kChanges},
          {"--title", "--title codes", Effect::kChanges}}});
}

// The design options of the families that use them; the others refuse them.
TEST_F(OptionEffect, CodeGenerate) {
  const std::vector<OptionCase> common = {{"--output", "", Effect::kPath},
                                          {"--length", "--length 20", Effect::kChanges}};
  CommandCase sinc{"code generate", "sinc --length 16 -o {W}/code.txt", common};
  sinc.options.push_back({"--velocity", "--velocity 1.5", Effect::kChanges});
  sinc.options.push_back({"--dt", "--dt 0.5", Effect::kChanges});
  sinc.options.push_back({"--seed", "--seed 3", Effect::kRefused});
  sinc.options.push_back({"--analog", "--analog", Effect::kRefused});
  check(sinc);
  CommandCase random{"code generate", "random --length 16 -o {W}/code.txt", common};
  random.options.push_back({"--velocity", "--velocity 1.5", Effect::kRefused});
  random.options.push_back({"--dt", "--dt 0.5", Effect::kRefused});
  random.options.push_back({"--seed", "--seed 3", Effect::kChanges});
  random.options.push_back({"--analog", "--analog", Effect::kChanges});
  check(random);
}

// The options of a code's figure of merit, as code analyze and optimize
// take them: the motion, the snr, the mode and the sensor (a full well is
// refused: the figure of merit is linear in the charge).
std::vector<OptionCase> design_cases() {
  std::vector<OptionCase> cases = {{"--velocity", "--velocity 1.5", Effect::kChanges},
                                   {"--dt", "--dt 0.5", Effect::kChanges},
                                   {"--snr", "--snr 20", Effect::kChanges},
                                   {"--mode", "--mode analog", Effect::kChanges}};
  for (const OptionCase& s : sensor_cases()) {
    cases.push_back(s);
    if (s.option == "--full-well") cases.back().effect = Effect::kRefused;
  }
  // The figure of merit under a regularised restoration (docs/method.md §12).
  cases.push_back({"--restoration", "--restoration wiener", Effect::kChanges});
  cases.push_back(
      {"--regularization", "--regularization 0.01", Effect::kChanges, "--restoration tikhonov"});
  cases.push_back({"--prior", "--prior power-law:1", Effect::kChanges, "--restoration wiener"});
  return cases;
}

TEST_F(OptionEffect, CodeAnalyze) {
  CommandCase c{"code analyze", "raskar", design_cases()};
  c.options.push_back({"--json", "--json {W}/analysis.json", Effect::kChanges});
  c.options.push_back({"--grid", "--grid 1024", Effect::kChanges});
  c.options.push_back(
      {"--velocity-distribution", "--velocity-distribution uniform:0.9:1.1", Effect::kChanges});
  check(c);
}

TEST_F(OptionEffect, CodeOptimize) {
  CommandCase c{"code optimize", "--length 6 --velocity 1 --restarts 2 --iterations 20",
                design_cases()};
  const std::vector<OptionCase> own = {
      {"--output", "--output {W}/code.txt", Effect::kChanges},
      {"--length", "--length 7", Effect::kChanges},
      {"--binary", "--binary", Effect::kChanges},
      // A light budget binds codes of gains in [0, 1]: analog or binary.
      {"--min-light", "--min-light 5", Effect::kChanges, "--mode analog"},
      {"--restarts", "--restarts 3", Effect::kChanges},
      {"--iterations", "--iterations 2", Effect::kChanges},
      {"--seed", "--seed 3", Effect::kChanges},
      // With the base's --velocity: exclusive (velocity_design_cli_test runs it alone).
      {"--velocity-distribution", "--velocity-distribution uniform:0.9:1.1", Effect::kRefused}};
  c.options.insert(c.options.end(), own.begin(), own.end());
  check(c);
  // Numerical frames of real gains have no light budget: refused there.
  const Results numerical = run(c.command, c.base + " --min-light 5");
  EXPECT_EQ(numerical.exit_code, 2) << numerical.err;
}

TEST_F(OptionEffect, Campaign) {
  CommandCase c{"campaign", "-i {IN} -c raskar -o {W}/c", {}};
  c.options = {
      {"--file", "", Effect::kPath},
      {"--input", "", Effect::kPath},
      {"--output", "", Effect::kPath},
      {"--code", "--code snapshot", Effect::kChanges},
      {"--mode", "--mode analog", Effect::kChanges},
      {"--velocity", "--velocity 1.5", Effect::kChanges},
      {"--restore-velocity", "--restore-velocity 1.1", Effect::kChanges},
      {"--snr", "--snr 20", Effect::kChanges},
      {"--dt", "--dt 0.5", Effect::kChanges},
      {"--trials", "--trials 2", Effect::kChanges},
      {"--seed", "--seed 7", Effect::kChanges},
      {"--noise", "--noise aggregated", Effect::kChanges},
      {"--rmse-margin", "--rmse-margin 100", Effect::kChanges},
      {"--per-trial", "--per-trial", Effect::kChanges},
      {"--threads", "--threads 1", Effect::kSame},
      {"--shard", "--shard 1/2", Effect::kChanges, "--velocity 1,1.5"},
      {"--figures", "--figures", Effect::kChanges, "--velocity 1,1.5"},
      {"--no-progress", "--no-progress", Effect::kSame},
      // Where every setting runs; its exit status over one that cannot: campaign_gaps_cli_test.
      {"--skip-unrunnable", "--skip-unrunnable", Effect::kSame},
      {"--restoration", "--restoration inverse,wiener", Effect::kChanges},
      {"--regularization", "--regularization 0.01", Effect::kChanges, "--restoration tikhonov"},
      {"--prior", "--prior oracle", Effect::kChanges, "--restoration wiener"},
      {"--velocity-distribution", "--velocity-distribution uniform:0.8:1.2", Effect::kChanges}};
  for (const OptionCase& s : sensor_cases()) c.options.push_back(s);
  check(c);
}

// merge: two shards of one campaign merged into one folder.
TEST_F(OptionEffect, CampaignMerge) {
  const fs::path parts = dir_ / "parts";
  for (const char* shard : {"1/2", "2/2"}) {
    const std::string part = (parts / std::string(1, shard[0])).string();
    ASSERT_EQ(test::run_fssim("campaign -i " + quote(input_) + " -c raskar -v 1,1.5 --shard " +
                              shard + " -o " + quote(part))
                  .exit_code,
              0);
  }
  check({"campaign merge",
         quote(parts / "1") + " " + quote(parts / "2") + " -o {W}/m",
         {{"--output", "", Effect::kPath},
          {"--figures", "--figures", Effect::kChanges},
          {"--skip-unrunnable", "--skip-unrunnable", Effect::kSame}}});
}

// check: a campaign against the same campaign with another seed: zero
// standard errors find a deviation (exit 1), each tolerance option passes
// it (exit 0); --exact changes the tolerance the summary states.
TEST_F(OptionEffect, CampaignCheck) {
  for (const char* seed : {"0", "1"}) {
    ASSERT_EQ(test::run_fssim("campaign -i " + quote(input_) + " -c raskar --trials 3 --seed " +
                              seed + " -o " + quote(dir_ / seed))
                  .exit_code,
              0);
  }
  const std::string results = quote(dir_ / "1" / "results.csv");
  const std::string expected = quote(dir_ / "0" / "results.csv");
  CommandCase c{"campaign check",
                results + " " + expected + " --columns rmse_mean,predicted_rmse --k-se 0",
                {{"--junit", "--junit {W}/junit.xml", Effect::kChanges},
                 {"--columns", "--columns predicted_rmse", Effect::kChanges},
                 {"--abs", "--abs 2", Effect::kChanges},
                 {"--rel", "--rel 0.5", Effect::kChanges},
                 {"--k-se", "--k-se 40", Effect::kChanges},
                 {"--exact", "--exact", Effect::kChanges},
                 // It compares RESULTS.csv with its own predictions, not with EXPECTED.csv.
                 {"--predicted", "--predicted --k-se 3", Effect::kRefused}}};
  c.verdicts = true;
  check(c);
}

// table: the results of a campaign of two velocities, 3 trials, as a table.
TEST_F(OptionEffect, CampaignTable) {
  ASSERT_EQ(test::run_fssim("campaign -i " + quote(input_) + " -c raskar -v 1,1.5 --trials 3 -o " +
                            quote(dir_ / "t"))
                .exit_code,
            0);
  check({"campaign table",
         quote(dir_ / "t" / "results.csv"),
         {{"--output", "", Effect::kPath},
          {"--format", "--format latex", Effect::kChanges},
          {"--columns", "--columns velocity,rmse_mean", Effect::kChanges},
          {"--digits", "--digits 4", Effect::kChanges}}});
}

// The sweep's rows are the simulator's runs: with a sensor, the same
// prediction as the simulator prints for each setting.
TEST_F(OptionEffect, SweepPredictsWithTheSensor) {
  const std::string sensor = "--read-noise 50 --dark-current 3";
  const CommandResult sweep =
      test::run_fssim("sweep -i " + quote(input_) + " --velocity 1:1.5:0.5 " + sensor + " -o -");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  const std::vector<std::string> rows = test::lines_of(sweep.out);
  ASSERT_EQ(rows.size(), 3u);
  for (const std::string& velocity : {"1", "1.5"}) {
    const CommandResult run =
        test::run_fssim("-i " + quote(input_) + " --velocity " + velocity + " " + sensor +
                        " --no-plots -o " + quote(dir_ / "run"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(run.out, m, std::regex("Predicted RMSE: ([0-9.]+)")));
    const double predicted = std::stod(m[1]);
    const std::string& row = rows[velocity == std::string("1") ? 1 : 2];
    std::vector<std::string> cells;
    std::stringstream cells_in(row);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 6u) << row;
    EXPECT_NEAR(std::stod(cells[5]), predicted, 1e-6) << row;  // predicted_rmse
  }
}

// A full well the image reaches clips readouts: the sweep's line says its
// prediction is approximate, as the simulator's does.
TEST_F(OptionEffect, SweepSaysWhenThePredictionIsApproximate) {
  const CommandResult clipped =
      test::run_fssim("sweep -i " + quote(input_) + " --full-well 500 -o -");
  ASSERT_EQ(clipped.exit_code, 0) << clipped.err;
  EXPECT_NE(clipped.err.find("(approximate: the sensor clips readouts)"), std::string::npos)
      << clipped.err;
  const CommandResult exact = test::run_fssim("sweep -i " + quote(input_) + " -o -");
  EXPECT_EQ(exact.err.find("approximate"), std::string::npos) << exact.err;
}

}  // namespace
}  // namespace fss
