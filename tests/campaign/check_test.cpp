// campaign check's rules (docs/campaign.md, "Regression checks"): the role of every results
// column, Student's t quantiles, the default comparison of each role, the refusals of a k-SE
// rule that cannot apply, and the JUnit names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "campaign/column_roles.h"
#include "campaign/student_t.h"
#include "fss/campaign/check.h"
#include "fss/campaign/results.h"
#include "support/test_util.h"

namespace fss {
namespace {

using column_roles::Role;

// Every column of results.csv (schemas 3 and 4) has one role, in the schema's order; each
// statistic's sd is a spread column naming it back, each derived column follows a statistic.
TEST(CheckColumnRoles, EveryResultsColumnHasOneRole) {
  const std::vector<ResultColumn>& columns = campaign_columns(true);
  const std::vector<column_roles::ColumnRole>& roles = column_roles::all();
  ASSERT_EQ(roles.size(), columns.size());
  for (std::size_t i = 0; i < columns.size(); ++i) {
    EXPECT_EQ(roles[i].name, columns[i].name) << i;
    EXPECT_EQ(column_roles::find(columns[i].name), &roles[i]);
    const column_roles::ColumnRole* partner = column_roles::find(roles[i].partner);
    switch (roles[i].role) {
      case Role::kStatistic:
        ASSERT_NE(partner, nullptr) << roles[i].name;
        EXPECT_EQ(partner->role, Role::kSpread);
        EXPECT_EQ(partner->partner, roles[i].name);
        break;
      case Role::kDerived:
        ASSERT_NE(partner, nullptr) << roles[i].name;
        EXPECT_EQ(partner->role, Role::kStatistic);
        break;
      case Role::kSpread:
        ASSERT_NE(partner, nullptr) << roles[i].name;
        break;
      default:
        EXPECT_EQ(partner, nullptr) << roles[i].name;
    }
    if (roles[i].fitted) EXPECT_EQ(roles[i].role, Role::kExact) << roles[i].name;
  }
  EXPECT_EQ(column_roles::find("rmse_maen"), nullptr);
  EXPECT_TRUE(column_roles::fits_to_noise("wiener", "power-law:2"));
  EXPECT_FALSE(column_roles::fits_to_noise("wiener", "oracle"));
  EXPECT_FALSE(column_roles::fits_to_noise("tikhonov", ""));
}

// Two-sided quantiles against the printed tables, nu = 1 against its closed form
// (P(|T| > t) = 1 - 2 atan(t) / pi), and the normal limit.
TEST(CheckStudentT, QuantilesAgreeWithTablesAndClosedForms) {
  EXPECT_NEAR(student_t::two_sided_quantile(0.05, 1), 12.706, 1e-3);
  EXPECT_NEAR(student_t::two_sided_quantile(0.05, 10), 2.228, 1e-3);
  EXPECT_NEAR(student_t::two_sided_quantile(0.01, 5), 4.032, 1e-3);
  EXPECT_NEAR(student_t::two_sided_quantile(0.001, 30), 3.646, 1e-3);
  EXPECT_NEAR(student_t::two_sided_quantile(0.05, 1e9), 1.960, 1e-3);
  // Beyond kMaxDegreesOfFreedom, that of kMaxDegreesOfFreedom: within 0.1 % of the normal's.
  EXPECT_NEAR(student_t::two_sided_quantile(1e-6, 1e9), 4.8916, 1e-3 * 4.8916);
  EXPECT_EQ(student_t::two_sided_quantile(1e-6, 1e9),
            student_t::two_sided_quantile(1e-6, student_t::kMaxDegreesOfFreedom));
  for (const double p : {0.3, 1e-3, 1e-6, 1e-10}) {
    const double t = student_t::two_sided_quantile(p, 1);
    EXPECT_NEAR(t, 1.0 / std::tan(std::numbers::pi * p / 2.0), 1e-9 * t) << p;
    for (const double nu : {2.0, 7.5, 19.0, 400.0}) {
      const double q = student_t::two_sided_quantile(p, nu);
      EXPECT_NEAR(student_t::two_sided_tail(q, nu), p, 1e-6 * p) << p << " " << nu;
      EXPECT_GT(q, student_t::two_sided_quantile(p, 2.0 * nu)) << "k falls as nu grows";
    }
  }
  EXPECT_EQ(student_t::two_sided_tail(0.0, 5), 1.0);
}

const char kHeader[] =
    "image,code,snr,seed,trials,rmse_mean,rmse_sd,psnr_mean,predicted_rmse,status\n";

// Two rows of 20 trials, rmse_sd 0.1: the combined standard error is 0.1 sqrt(2 / 20) = 0.0316.
std::string rows(double rmse_raskar, double rmse_mip, const std::string& predicted = "2.3") {
  return std::string(kHeader) + "a.png,raskar,100,1,20," + std::to_string(rmse_raskar) +
         ",0.1,40," + predicted + ",ok\n" + "a.png,mip,100,2,20," + std::to_string(rmse_mip) +
         ",0.1,40,2.2,ok\n";
}

// Without options: rmse_mean within the default k (Student-t, 19 degrees of freedom, 0.1 %
// over its 2 comparisons), predicted_rmse within rel 1e-9, status equal, psnr_mean left out.
TEST(CheckDefaults, StatisticsWithinKStandardErrorsExactWithinRoundOff) {
  const double se = 0.1 * std::sqrt(2.0 / 20.0);
  const double k = student_t::two_sided_quantile(kCheckFalseAlarmRate / 2.0, 19.0);
  EXPECT_GT(k, 4.0);
  EXPECT_LT(k, 6.0);
  const std::string expected = rows(2.3, 2.2);
  const CheckReport near = CheckCampaignResults(rows(2.3 + 0.98 * k * se, 2.2 - 0.98 * k * se),
                                                "r.csv", expected, "e.csv", {});
  EXPECT_EQ(near.failures(), 0);
  ASSERT_EQ(near.cases.size(), 6u);  // rmse_mean, predicted_rmse, status of 2 rows
  const CheckReport far =
      CheckCampaignResults(rows(2.3 + 1.02 * k * se, 2.2), "r.csv", expected, "e.csv", {});
  ASSERT_EQ(far.failures(), 1);
  EXPECT_EQ(far.cases[0].column, "rmse_mean");
  EXPECT_NE(far.cases[0].message.find(format_number(k, 4) + " SE"), std::string::npos)
      << far.cases[0].message;
  const std::vector<std::string> summary = far.summary;
  ASSERT_EQ(summary.size(), 4u);
  EXPECT_EQ(summary[0].rfind("compared rmse_mean: within k = " + format_number(k, 3) +
                                 " standard errors (Student-t, 19 degrees of freedom",
                             0),
            0u)
      << summary[0];
  EXPECT_NE(summary[0].find("among these 2 comparisons has a chance below 0.1 %"),
            std::string::npos);
  EXPECT_EQ(summary[1], "compared predicted_rmse: within rel 1e-09");
  EXPECT_EQ(summary[2], "compared status: equal");
  EXPECT_EQ(summary[3], "left out psnr_mean: follows rmse_mean");
}

// An exact column 1e-12 off (relative) passes by default and fails with --exact; --rel
// replaces the default 1e-9.
TEST(CheckDefaults, ExactColumnsWithinRoundOffOrBitwise) {
  const std::string expected = rows(2.3, 2.2, "2.3");
  const std::string results = rows(2.3, 2.2, "2.3000000000023");
  EXPECT_EQ(CheckCampaignResults(results, "r", expected, "e", {}).failures(), 0);
  CheckOptions exact;
  exact.exact = true;
  const CheckReport bitwise = CheckCampaignResults(results, "r", expected, "e", exact);
  ASSERT_EQ(bitwise.failures(), 1);
  EXPECT_FALSE(bitwise.cases[1].passed);
  EXPECT_EQ(bitwise.cases[1].column, "predicted_rmse");
  EXPECT_EQ(bitwise.summary[1], "compared predicted_rmse, status: equal");
  EXPECT_EQ(CheckCampaignResults(expected, "r", expected, "e", exact).failures(), 0);
  CheckOptions rel;
  rel.rel_tolerance = 1e-13;
  EXPECT_EQ(CheckCampaignResults(results, "r", expected, "e", rel).failures(), 1);
  rel.exact = true;
  EXPECT_TRUE(test::throws_error([&] { CheckCampaignResults(results, "r", expected, "e", rel); },
                                 ErrorKind::kUsage, {"--exact", "without --abs and --rel"}));
}

// --abs or --rel given without --k-se: the statistics within them only (a difference of one
// standard error fails a tight --rel); --k-se K alone: K standard errors.
TEST(CheckDefaults, GivenTolerancesReplaceTheDefaults) {
  const std::string results = rows(2.3 + 0.0316, 2.2);
  const std::string expected = rows(2.3, 2.2);
  CheckOptions rel;
  rel.rel_tolerance = 1e-6;
  const CheckReport strict = CheckCampaignResults(results, "r", expected, "e", rel);
  EXPECT_EQ(strict.failures(), 1);
  EXPECT_EQ(strict.summary[0], "compared rmse_mean, predicted_rmse: within rel 1e-06");
  CheckOptions k;
  k.k_standard_errors = 0.5;
  EXPECT_EQ(CheckCampaignResults(results, "r", expected, "e", k).failures(), 1);
  k.k_standard_errors = 1.5;
  const CheckReport loose = CheckCampaignResults(results, "r", expected, "e", k);
  EXPECT_EQ(loose.failures(), 0);
  EXPECT_EQ(loose.summary[0], "compared rmse_mean: within 1.5 standard errors, or rel 1e-09");
  // A derived column named: compared within --abs or --rel, refused without.
  CheckOptions psnr;
  psnr.columns = {"psnr_mean"};
  EXPECT_TRUE(test::throws_error([&] { CheckCampaignResults(results, "r", expected, "e", psnr); },
                                 ErrorKind::kUsage, {"psnr_mean follows rmse_mean", "--abs"}));
  psnr.abs_tolerance = 0.01;
  EXPECT_EQ(CheckCampaignResults(results, "r", expected, "e", psnr).failures(), 0);
}

// A k-SE rule that cannot apply is refused in one line saying what it needs: an sd or trials
// column missing from a file, fewer than 2 trials in a row, no statistic compared.
TEST(CheckDefaults, RefusesAStandardErrorItCannotEstimate) {
  const std::string results = rows(2.3, 2.2);
  const std::string no_sd = "image,code,snr,rmse_mean\na.png,raskar,100,2.3\n";
  CheckOptions k;
  k.k_standard_errors = 4;
  EXPECT_TRUE(test::throws_error([&] { CheckCampaignResults(results, "r.csv", no_sd, "e.csv", k); },
                                 ErrorKind::kUsage,
                                 {"--k-se 4: 'e.csv' has no column 'rmse_sd'",
                                  "rmse_sd and trials (2 or more) in both "
                                  "files",
                                  "--abs or --rel"}));
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignResults(results, "r.csv", no_sd, "e.csv", {}); }, ErrorKind::kUsage,
      {"'e.csv' has no column 'rmse_sd': by default rmse_mean is "
       "compared within k standard errors"}));
  const std::string one_trial =
      "image,code,snr,trials,rmse_mean,rmse_sd\na.png,raskar,100,20,2.3,0.1\n"
      "a.png,mip,100,1,2.2,0\n";
  for (const CheckOptions& options : {k, CheckOptions{}}) {
    const std::optional<Error> error = test::error_of(
        [&] { CheckCampaignResults(results, "r.csv", one_trial, "e.csv", options); });
    ASSERT_TRUE(error.has_value());
    const std::string message = error->what();
    EXPECT_NE(message.find("line 3 of 'e.csv' (image=a.png code=mip) has trials 1"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("(2 or more)"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
  // With --abs the row is compared without a standard error.
  CheckOptions abs;
  abs.abs_tolerance = 0.01;
  EXPECT_EQ(CheckCampaignResults(results, "r.csv", one_trial, "e.csv", abs).failures(), 0);
  CheckOptions exact_only = k;
  exact_only.columns = {"predicted_rmse"};
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignResults(results, "r.csv", results, "e.csv", exact_only); },
      ErrorKind::kUsage, {"--k-se 4: it applies to the means over the trials"}));
}

// The outputs Wiener's power-law prior fits to a noise draw depend on the seed: compared when
// both files show the same seed (or within --abs or --rel), left out otherwise.
TEST(CheckDefaults, FittedOutputsAreComparedUnderTheSameSeedOnly) {
  const auto file = [](const std::string& seed, const std::string& level) {
    return "image,code,restoration,prior,seed,trials,rmse_mean,rmse_sd,prior_level\n"
           "a.png,raskar,wiener,power-law:2," +
           seed + ",20,2.3,0.1," + level + "\n" + "a.png,raskar,wiener,oracle," + seed +
           ",20,2.3,0.1,\n";
  };
  const CheckReport same = CheckCampaignResults(file("7", "200"), "r", file("7", "200"), "e", {});
  EXPECT_EQ(same.cases.size(), 4u);
  EXPECT_EQ(same.failures(), 0);
  const CheckReport other = CheckCampaignResults(file("8", "203"), "r", file("7", "200"), "e", {});
  EXPECT_EQ(other.cases.size(), 3u);
  EXPECT_EQ(other.failures(), 0);
  ASSERT_EQ(other.summary.size(), 3u);
  EXPECT_EQ(other.summary[2].rfind("left out prior_level in 1 rows: Wiener's power-law prior", 0),
            0u)
      << other.summary[2];
  CheckOptions rel;
  rel.rel_tolerance = 0.01;
  EXPECT_EQ(CheckCampaignResults(file("8", "203"), "r", file("7", "200"), "e", rel).failures(), 1);
}

// JUnit: one test case per comparison, named by its setting and column, its class the suite
// and the column.
TEST(CheckDefaults, JunitNamesEachSetting) {
  const CheckReport report = CheckCampaignResults(
      rows(2.3, 9), "r", rows(2.3, 2.2) + "a.png,sinc,100,3,20,1,0.1,40,1,ok\n", "e", {});
  const std::string xml = check_junit_xml(report, "suite");
  EXPECT_NE(xml.find("<testcase classname=\"suite.rmse_mean\" name=\"image=a.png code=raskar: "
                     "rmse_mean\"/>"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<testcase classname=\"suite.rmse_mean\" name=\"image=a.png code=mip: "
                     "rmse_mean\">\n    <failure message=\"image=a.png code=mip: rmse_mean 9"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<testcase classname=\"suite.row\" name=\"image=a.png code=sinc: row\">"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("tests=\"7\" failures=\"2\""), std::string::npos) << xml;
}

// --predicted: without a tolerance, the default k over the rows compared, nu = trials - 1.
TEST(CheckDefaults, PredictionsWithinTheDefaultK) {
  const std::string results =
      "code,trials,rmse_mean,rmse_sd,predicted_rmse,status\n"
      "raskar,10,2.0,0.1,2.1,ok\n"  // z = -3.2
      "mip,10,2.0,0.1,2.3,ok\n";    // z = -9.5
  const double k = student_t::two_sided_quantile(kCheckFalseAlarmRate / 2.0, 9.0);
  ASSERT_GT(k, 3.2 * 1.01);
  ASSERT_LT(k, 9.5 / 1.01);
  const CheckReport report = CheckCampaignPredictions(results, "r.csv", {});
  ASSERT_EQ(report.cases.size(), 2u);
  EXPECT_TRUE(report.cases[0].passed) << report.cases[0].message;
  EXPECT_FALSE(report.cases[1].passed);
  ASSERT_EQ(report.summary.size(), 1u);
  EXPECT_EQ(report.summary[0].rfind("compared rmse_mean with predicted_rmse: within k = " +
                                        format_number(k, 3) + " standard errors",
                                    0),
            0u)
      << report.summary[0];
  CheckOptions exact;
  exact.exact = true;
  EXPECT_TRUE(test::throws_error([&] { CheckCampaignPredictions(results, "r.csv", exact); },
                                 ErrorKind::kUsage, {"--exact"}));
}

}  // namespace
}  // namespace fss
