// End-to-end tests of `fssim code analyze | optimize --velocity-distribution`
// (docs/designing-codes.md, docs/method.md §13): the averaged figure in the `SNR at level 100:`
// line with the distribution, the quadrature and the worst velocity; a point distribution gives
// the single-velocity figures; the JSON; the optimizer's report and code file; and one-line
// refusals with exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/test_util.h"

namespace fss {
namespace {

using test::CommandResult;
using test::lines_of;
using test::quote;
using test::run_fssim;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// The line that starts with `label`, or "" (with a failure).
std::string line_starting(const std::string& out, const std::string& label) {
  for (const std::string& line : lines_of(out)) {
    if (line.rfind(label, 0) == 0) return line;
  }
  ADD_FAILURE() << "no line '" << label << "...' in:\n" << out;
  return "";
}

// The number after "label: " on the line that starts with it.
double value_after(const std::string& out, const std::string& label) {
  const std::string line = line_starting(out, label + ": ");
  return line.empty() ? std::nan("") : std::stod(line.substr(label.size() + 2));
}

// The SNR of the line "Worst velocity: V (SNR at level 100 there: S)".
double worst_snr(const std::string& out) {
  const std::string line = line_starting(out, "Worst velocity: ");
  const std::size_t at = line.find("there: ");
  return at == std::string::npos ? std::nan("") : std::stod(line.substr(at + 7));
}

TEST(VelocityDesignCli, AnalyzePrintsTheAveragedFigureTheDistributionAndTheWorstVelocity) {
  const CommandResult r = run_fssim("code analyze raskar --velocity-distribution uniform:0.5:1.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Setting: numerical mode, velocity distribution uniform:0.5:1.5, "
                               "dt 1, snr 100\n"));
  EXPECT_THAT(r.out, HasSubstr("Velocity distribution: uniform on [0.5, 1.5]\n"));
  EXPECT_THAT(line_starting(r.out, "Averaged over it"),
              HasSubstr("adaptive Gauss-Kronrod quadrature to relative 1e-4 ("));
  EXPECT_THAT(r.out, HasSubstr("Worst velocity: 1.5 (SNR at level 100 there: "));
  const double averaged = value_after(r.out, "SNR at level 100");
  const double at_one = value_after(run_fssim("code analyze raskar").out, "SNR at level 100");
  // Faster velocities blur more: the average is below v = 1's 48.13, above v = 1.5's.
  EXPECT_LT(averaged, at_one);
  const double at_top =
      value_after(run_fssim("code analyze raskar --velocity 1.5").out, "SNR at level 100");
  EXPECT_GT(averaged, at_top);
  // raskar's worst velocity is the fastest.
  EXPECT_NEAR(worst_snr(r.out), at_top, 1e-6);
  EXPECT_THAT(r.out, HasSubstr("Bound on the SNR at level 100 (any code, any length, the bound "
                               "of Q M averaged over the velocities): "));
}

TEST(VelocityDesignCli, ANormalWithoutBoundsSaysItWasTruncated) {
  const CommandResult r = run_fssim("code analyze sinc --velocity-distribution normal:1:0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Velocity distribution: normal of mean 1, sd 0.1, truncated at "
                               "mean +/- 4 sd to [0.6, 1.4] and renormalised\n"));
}

TEST(VelocityDesignCli, APointDistributionPrintsTheSingleVelocityFigures) {
  test::TempDir dir;
  test::write_file(dir / "one.txt", "1.2 1\n");
  const std::string single = run_fssim("code analyze mip --velocity 1.2 --restoration wiener").out;
  for (const std::string spec : {std::string("uniform:1.2:1.2"), quote(dir / "one.txt")}) {
    const CommandResult r =
        run_fssim("code analyze mip --restoration wiener --velocity-distribution " + spec);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string label : {"SNR at level 100: ", "Snapshot SNR at level 100: ",
                                    "Ratio to the snapshot: ", "M (mean"}) {
      EXPECT_EQ(line_starting(r.out, label), line_starting(single, label)) << spec;
    }
    EXPECT_THAT(r.out, HasSubstr("one velocity (the single-velocity figure)")) << spec;
  }
}

TEST(VelocityDesignCli, WithoutADistributionTheOutputIsUnchanged) {
  const CommandResult r = run_fssim("code analyze raskar");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, Not(HasSubstr("distribution")));
  EXPECT_THAT(r.out, Not(HasSubstr("Worst velocity")));
  EXPECT_THAT(r.out, HasSubstr("SNR at level 100: 48.127577\n"));
  const nlohmann::json j = nlohmann::json::parse(run_fssim("code analyze raskar --json -").out);
  EXPECT_FALSE(j["parameters"].contains("velocity_distribution"));
  EXPECT_EQ(j["parameters"]["velocity"].get<double>(), 1.0);
}

TEST(VelocityDesignCli, TheJsonRecordsTheDistributionTheWorstVelocityAndTheQuadrature) {
  const CommandResult r =
      run_fssim("code analyze random --velocity-distribution normal:1:0.2:0.5:1.5 --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& d = j["parameters"]["velocity_distribution"];
  EXPECT_EQ(d["spec"], "normal:1:0.2:0.5:1.5");
  EXPECT_EQ(d["low"].get<double>(), 0.5);
  EXPECT_EQ(d["sd"].get<double>(), 0.2);
  EXPECT_FALSE(j["parameters"].contains("velocity"));
  const nlohmann::json& a = j["analysis"];
  const double e = a["restoration_error"].get<double>();
  EXPECT_NEAR(a["snr_level100"].get<double>(), 100.0 / std::sqrt(e), 1e-9);
  EXPECT_GT(a["worst_velocity"].get<double>(), 0.5);
  EXPECT_LE(a["worst_velocity"].get<double>(), 1.5);
  EXPECT_LT(a["worst_snr_level100"].get<double>(), a["snr_level100"].get<double>());
  EXPECT_GT(a["quadrature"]["evaluations"].get<int>(), 0);
  EXPECT_EQ(a["quadrature"]["relative_tolerance"].get<double>(), 1e-4);
  EXPECT_TRUE(a["quadrature"]["converged"].get<bool>());
  EXPECT_LE(a["quadrature"]["error_estimate"].get<double>(), 1e-4 * e);
}

TEST(VelocityDesignCli, ItWorksWithTheModesTheSensorAndTheRestorations) {
  test::TempDir dir;
  test::write_file(dir / "v.txt", "# velocity weight\n0.8 1\n1.0 2\n1.3 1\n");
  const std::string file = quote(dir / "v.txt");
  for (const std::string options :
       {"--mode analog --read-noise 4", "--restoration wiener --prior power-law:2:100",
        "--restoration tikhonov --snr 20", "--restoration tikhonov --regularization 0.01",
        "--dark-current 1 --adc-bits 10 --adc-gain 2"}) {
    for (const std::string spec : {std::string("uniform:0.8:1.3"), file}) {
      const std::string arguments =
          "code analyze raskar " + options + " --velocity-distribution " + spec;
      const CommandResult r = run_fssim(arguments);
      ASSERT_EQ(r.exit_code, 0) << arguments << "\n" << r.err;
      const double averaged = value_after(r.out, "SNR at level 100");
      EXPECT_GT(averaged, 0.0) << arguments;
      // No better than the average: the worst velocity's.
      EXPECT_LE(worst_snr(r.out), averaged) << arguments;
    }
  }
  const CommandResult discrete = run_fssim("code analyze raskar --velocity-distribution " + file);
  EXPECT_THAT(discrete.out, HasSubstr("the exact weighted sum over its 3 velocities"));
}

TEST(VelocityDesignCli, ACodeNotInvertibleOverTheSupportIsSaidSo) {
  const CommandResult r =
      run_fssim("code analyze accumulation --velocity-distribution uniform:0.5:1.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("SNR at level 100: 0.000000\n"));
  EXPECT_THAT(r.out, HasSubstr("Not invertible at velocity 1.5: the expected error is infinite\n"));
  EXPECT_THAT(r.out, HasSubstr("Invertible: no (K vanishes on the band within the support)\n"));
}

TEST(VelocityDesignCli, OptimizeReportsTheRulesAndWritesACodeThatAnalyzesTheSame) {
  test::TempDir dir;
  const std::string code = quote(dir / "best.txt");
  const CommandResult r = run_fssim(
      "code optimize -L 12 --velocity-distribution uniform:0.5:1.5 --restarts 1 --iterations 40 "
      "-o " +
      code);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Optimized numerical code: L = 12, dt 1\n"));
  EXPECT_THAT(r.out, HasSubstr("Velocity: uniform on [0.5, 1.5]; criterion averaged over it: "
                               "composite Gauss rule 8 panels x 4 nodes (optimisation), "
                               "adaptive Gauss-Kronrod to 1e-4 (reported figure: "));
  EXPECT_THAT(r.out, HasSubstr("Worst velocity in the support: "));
  EXPECT_THAT(r.out, HasSubstr("under the same velocity distribution and dt:"));
  EXPECT_THAT(test::read_file(dir / "best.txt"),
              HasSubstr("velocity distribution uniform:0.5:1.5"));
  const CommandResult analysed =
      run_fssim("code analyze " + code + " --velocity-distribution uniform:0.5:1.5");
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  const std::string reported = line_starting(r.out, "SNR at level 100: ");
  const double snr = std::stod(reported.substr(18));
  EXPECT_NEAR(value_after(analysed.out, "SNR at level 100"), snr, 1e-4);
}

TEST(VelocityDesignCli, OptimizeWithBinaryGainsAndASensorUnderADistribution) {
  const CommandResult r = run_fssim(
      "code optimize -L 12 --binary --min-light 4 --read-noise 2 --velocity-distribution "
      "normal:1:0.2 --restarts 1 --iterations 20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Velocity: normal of mean 1, sd 0.2, truncated at mean +/- 4 sd"));
  EXPECT_GT(value_after(r.out, "SNR at level 100"), 0.0);
}

TEST(VelocityDesignCli, HelpShowsTheOption) {
  for (const std::string command : {"code analyze --help", "code optimize --help"}) {
    const CommandResult r = run_fssim(command);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_THAT(r.out, HasSubstr("--velocity-distribution")) << command;
  }
}

struct Refusal {
  const char* name;
  const char* arguments;
  const char* culprit;
};

void PrintTo(const Refusal& c, std::ostream* os) { *os << c.arguments; }

class VelocityDesignRefusals : public ::testing::TestWithParam<Refusal> {};

TEST_P(VelocityDesignRefusals, ExitTwoWithOneLineNamingTheOption) {
  const CommandResult r = run_fssim(GetParam().arguments);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::vector<std::string> lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_THAT(lines[0], StartsWith("fssim: error:"));
  EXPECT_THAT(lines[0], HasSubstr(GetParam().culprit));
  EXPECT_LE(r.err.size(), 300u) << r.err;
  EXPECT_EQ(r.out, "");
}

INSTANTIATE_TEST_SUITE_P(
    Options, VelocityDesignRefusals,
    ::testing::Values(
        Refusal{"AnalyzeBothVelocities",
                "code analyze raskar --velocity 1 --velocity-distribution uniform:0.5:1.5",
                "--velocity-distribution and --velocity are exclusive"},
        Refusal{"OptimizeBothVelocities",
                "code optimize -L 8 -v 1 --velocity-distribution uniform:0.5:1.5",
                "--velocity-distribution and --velocity are exclusive"},
        Refusal{"BadSpec", "code analyze raskar --velocity-distribution uniform:1",
                "--velocity-distribution"},
        Refusal{"UnknownKind", "code analyze raskar --velocity-distribution gauss:1:2",
                "--velocity-distribution"},
        Refusal{"MissingFile", "code analyze raskar --velocity-distribution no/such/file.txt",
                "--velocity-distribution"},
        Refusal{"SupportTooFast", "code analyze raskar --velocity-distribution uniform:0.5:2.5",
                "|v| dt < 2"},
        Refusal{"NormalTooWide", "code optimize -L 8 --velocity-distribution normal:1:0.5",
                "which reaches |v| dt = 3"},
        Refusal{"SupportTooFastWithDt",
                "code analyze raskar --dt 2 --velocity-distribution uniform:0.5:1", "--dt 2"},
        Refusal{"OptimizeStillPoint", "code optimize -L 8 --velocity-distribution uniform:0:0",
                "0 < |velocity| dt < 2"},
        Refusal{"OptimizeNoVelocity", "code optimize -L 8", "--velocity"}),
    [](const ::testing::TestParamInfo<Refusal>& info) { return info.param.name; });

}  // namespace
}  // namespace fss
