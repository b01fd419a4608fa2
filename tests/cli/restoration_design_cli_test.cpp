// End-to-end tests of `fssim code analyze | optimize` under a restoration (--restoration,
// --prior, --regularization; docs/designing-codes.md): the default is the inverse filter byte
// for byte, the criterion is printed and recorded, and every option for the wrong method, an
// oracle prior and a value out of range is refused with one line.
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

// The number after "label: " on the line that starts with it.
double value_after(const std::string& out, const std::string& label) {
  for (const std::string& line : lines_of(out)) {
    if (line.rfind(label + ": ", 0) == 0) return std::stod(line.substr(label.size() + 2));
  }
  ADD_FAILURE() << "no line '" << label << ": ...' in:\n" << out;
  return std::nan("");
}

TEST(RestorationDesignCli, DefaultIsTheInverseFilterByteForByte) {
  const CommandResult plain = run_fssim("code analyze raskar");
  const CommandResult inverse = run_fssim("code analyze raskar --restoration inverse");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.out, inverse.out);
  EXPECT_THAT(plain.out, Not(HasSubstr("Criterion")));
  // The README's figures.
  EXPECT_THAT(plain.out, HasSubstr("SNR at level 100: 48.127577\n"));
  EXPECT_THAT(plain.out,
              HasSubstr("Bound on the SNR at level 100 (any code, any length): 85.745378\n"));
  const CommandResult json = run_fssim("code analyze raskar --json -");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_FALSE(nlohmann::json::parse(json.out)["parameters"].contains("restoration"));
  const std::string small = "code optimize -L 8 -v 1 --restarts 2 --iterations 30";
  const CommandResult optimized = run_fssim(small);
  ASSERT_EQ(optimized.exit_code, 0) << optimized.err;
  EXPECT_EQ(optimized.out, run_fssim(small + " --restoration inverse").out);
  EXPECT_THAT(optimized.out, HasSubstr("Cauchy-Schwarz bound 85."));
}

TEST(RestorationDesignCli, WienerAnalysisPrintsItsCriterionAndNoBound) {
  const CommandResult r = run_fssim("code analyze raskar --restoration wiener");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Criterion: wiener restoration, power-law prior gamma 2, C 180 "
                               "(stationary expected error at level 100)\n"));
  EXPECT_THAT(r.out, HasSubstr("the Cauchy-Schwarz bound is the inverse filter's"));
  EXPECT_THAT(r.out, Not(HasSubstr("any code, any length")));
  const double wiener = value_after(r.out, "SNR at level 100");
  // Better than the inverse filter's 48.13, by less than a factor 2 at snr 100.
  EXPECT_GT(wiener, 48.2);
  EXPECT_LT(wiener, 96.0);
  // The prior's level: a huge C gives back the inverse filter.
  const CommandResult huge =
      run_fssim("code analyze raskar --restoration wiener --prior power-law:2:1e100");
  EXPECT_NEAR(value_after(huge.out, "SNR at level 100"), 48.127577, 1e-5);
  // A smaller gamma changes the figure.
  const CommandResult flatter = run_fssim(
      "code analyze raskar --restoration wiener --prior "
      "power-law:1");
  EXPECT_NE(value_after(flatter.out, "SNR at level 100"), wiener);
}

TEST(RestorationDesignCli, TheAccumulationCodeIsFiniteUnderWienerAndTikhonov) {
  for (const std::string restoration : {"wiener", "tikhonov"}) {
    const CommandResult r =
        run_fssim("code analyze accumulation --json - --restoration " + restoration);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["analysis"]["invertible"].get<bool>());
    EXPECT_TRUE(j["analysis"]["m"].is_null());
    EXPECT_GT(j["analysis"]["snr_level100"].get<double>(), 1.0) << restoration;
    EXPECT_TRUE(j["analysis"]["snr_level100_bound"].is_null());
    EXPECT_GT(j["analysis"]["restoration_error"].get<double>(), 0.0);
  }
}

TEST(RestorationDesignCli, TikhonovReportsItsLambdaAndTheJsonRecordsTheRestoration) {
  const CommandResult r = run_fssim("code analyze mip --restoration tikhonov --snr 20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Criterion: tikhonov restoration, lambda optimal in [1e-08, 100], "
                               "its bias measured under the default power-law prior gamma 2, C "
                               "180"));
  EXPECT_THAT(r.out, HasSubstr("Regularization: lambda "));
  const CommandResult json =
      run_fssim("code analyze mip --restoration tikhonov --regularization 0.003 --json -");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  const nlohmann::json& restoration = j["parameters"]["restoration"];
  EXPECT_EQ(restoration["method"], "tikhonov");
  EXPECT_EQ(restoration["prior"], "power-law");
  EXPECT_EQ(restoration["gamma"].get<double>(), 2.0);
  EXPECT_EQ(restoration["C"].get<double>(), 180.0);
  EXPECT_EQ(restoration["lambda"].get<double>(), 0.003);
  EXPECT_FALSE(restoration["lambda_optimal"].get<bool>());
  const double e = j["analysis"]["restoration_error"].get<double>();
  EXPECT_NEAR(j["analysis"]["snr_level100"].get<double>(), 100.0 / std::sqrt(e), 1e-9);

  const CommandResult w =
      run_fssim("code analyze mip --restoration wiener --prior power-law:1.5:40 --json -");
  const nlohmann::json wj = nlohmann::json::parse(w.out)["parameters"]["restoration"];
  EXPECT_EQ(wj["method"], "wiener");
  EXPECT_EQ(wj["gamma"].get<double>(), 1.5);
  EXPECT_EQ(wj["C"].get<double>(), 40.0);
  EXPECT_FALSE(wj.contains("lambda"));
}

TEST(RestorationDesignCli, OptimizeUnderWienerBeatsRaskarAndWritesTheCriterion) {
  test::TempDir dir;
  const std::string code = quote(dir / "best.txt");
  const CommandResult r = run_fssim(
      "code optimize -L 52 -v 1 --mode analog --snr 10 --restarts 2 --iterations 100 "
      "--restoration wiener -o " +
      code);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Criterion: wiener restoration"));
  EXPECT_THAT(r.out, HasSubstr("the Cauchy-Schwarz bound is for the inverse filter only"));
  // The paper codes under the same criterion: the accumulation code has a figure.
  EXPECT_THAT(r.out, Not(HasSubstr("not invertible")));
  const std::string file = test::read_file(dir / "best.txt");
  EXPECT_THAT(file, HasSubstr("# criterion: wiener restoration"));
  const CommandResult ours =
      run_fssim("code analyze " + code + " --mode analog --snr 10 --restoration wiener");
  const CommandResult raskar =
      run_fssim("code analyze raskar --mode analog --snr 10 --restoration wiener");
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  EXPECT_GT(value_after(ours.out, "SNR at level 100"),
            1.05 * value_after(raskar.out, "SNR at level 100"));
}

struct Refusal {
  const char* name;
  const char* arguments;
  const char* culprit;
};

void PrintTo(const Refusal& c, std::ostream* os) { *os << c.arguments; }

class RestorationRefusals : public ::testing::TestWithParam<Refusal> {};

TEST_P(RestorationRefusals, ExitTwoWithOneLineNamingTheOption) {
  const CommandResult r = run_fssim(GetParam().arguments);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::vector<std::string> lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_THAT(lines[0], StartsWith("fssim: error:"));
  EXPECT_THAT(lines[0], HasSubstr(GetParam().culprit));
  EXPECT_LE(r.err.size(), 250u) << r.err;
  EXPECT_EQ(r.out, "");
}

INSTANTIATE_TEST_SUITE_P(
    Options, RestorationRefusals,
    ::testing::Values(
        Refusal{"PriorWithInverse", "code analyze raskar --prior power-law", "--prior power-law"},
        Refusal{"PriorWithTikhonov",
                "code analyze raskar --restoration tikhonov --prior power-law:2", "--prior"},
        Refusal{"RegularizationWithInverse", "code analyze raskar --regularization 0.1",
                "--regularization 0.1"},
        Refusal{"RegularizationWithWiener",
                "code analyze raskar --restoration wiener --regularization optimal",
                "--regularization"},
        Refusal{"OracleInAnalyze", "code analyze raskar --restoration wiener --prior oracle",
                "no image"},
        Refusal{"OracleInOptimize", "code optimize -L 8 -v 1 --restoration wiener --prior oracle",
                "no image"},
        Refusal{"GammaTooLarge", "code analyze raskar --restoration wiener --prior power-law:9",
                "GAMMA must lie in [0, 8]"},
        Refusal{"NegativeGamma", "code analyze raskar --restoration wiener --prior power-law:-1",
                "GAMMA"},
        Refusal{"ZeroLevel", "code analyze raskar --restoration wiener --prior power-law:2:0",
                "C must lie in"},
        Refusal{"NanLevel", "code analyze raskar --restoration wiener --prior power-law:2:nan",
                "C is not a finite number"},
        Refusal{"UnknownPrior", "code analyze raskar --restoration wiener --prior gauss",
                "--prior 'gauss'"},
        Refusal{"LambdaTooLarge", "code analyze raskar --restoration tikhonov --regularization 1e3",
                "--regularization 1e3: must be a number in [1e-08, 100]"},
        Refusal{"LambdaTooSmall",
                "code optimize -L 8 -v 1 --restoration tikhonov --regularization 1e-9",
                "--regularization 1e-9"},
        Refusal{"LambdaNotANumber",
                "code analyze raskar --restoration tikhonov --regularization best",
                "--regularization best"},
        Refusal{"UnknownRestoration", "code analyze raskar --restoration ridge", "--restoration"},
        Refusal{"GridWithWiener", "code analyze raskar --restoration wiener --grid 920",
                "--grid 920"},
        Refusal{"PriorWithInverseOptimize", "code optimize -L 8 -v 1 --prior power-law:2:180",
                "--prior"}),
    [](const ::testing::TestParamInfo<Refusal>& info) { return info.param.name; });

}  // namespace
}  // namespace fss
