// Tests of campaign tables (fss/campaign/table.h): the columns chosen, the
// caption of the fixed settings, mean ± standard error rounded together, the
// three formats and their escaping, the rows that did not run, refusals.
#include "fss/campaign/table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "campaign/table_numbers.h"
#include "fss/campaign/results.h"
#include "fss/core/error.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Row = std::map<std::string, std::string>;

// A row of a numerical campaign on camera.png at v = 1, snr 100, 20 trials,
// with `changes` over it.
Row row(const Row& changes) {
  Row r = {{"image", "data/camera.png"},
           {"code", "raskar"},
           {"mode", "numerical"},
           {"velocity", "1"},
           {"restore_velocity", "1"},
           {"snr", "100"},
           {"dt", "1"},
           {"read_noise", "0"},
           {"restoration", "inverse"},
           {"noise", "poisson"},
           {"rmse_margin", "-1"},
           {"seed", "7"},
           {"trials", "20"},
           {"blur_length", "52"},
           {"rmse_mean", "2.354321"},
           {"rmse_sd", "0.0139"},
           {"rmse_ci_mean", "2.5341"},
           {"rmse_ci_sd", "0.00671"},
           {"predicted_rmse", "2.35049"},
           {"status", "ok"}};
  for (const auto& [key, value] : changes) r[key] = value;
  return r;
}

// results.csv text of `rows`, in the columns of schema 3 (4 with
// distributions); cells quoted when they need it.
std::string results(const std::vector<Row>& rows, bool distributions = false) {
  const std::vector<ResultColumn>& columns = campaign_columns(distributions);
  const auto cell = [](const std::string& text) {
    if (text.find_first_of(",\"") == std::string::npos) return text;
    std::string quoted = "\"";
    for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
  };
  std::string text;
  for (std::size_t i = 0; i < columns.size(); ++i)
    text += (i ? "," : "") + std::string(columns[i].name);
  text += "\n";
  for (const Row& r : rows) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const auto it = r.find(columns[i].name);
      text += (i ? "," : "") + cell(it == r.end() ? "" : it->second);
    }
    text += "\n";
  }
  return text;
}

std::string table(const std::string& csv, TableFormat format = TableFormat::kMarkdown,
                  std::vector<std::string> columns = {}, int digits = 2) {
  TableOptions options;
  options.format = format;
  options.columns = std::move(columns);
  options.digits = digits;
  return campaign_table(csv, "results.csv", options);
}

// Two codes at two snr values.
std::string two_by_two() {
  return results({row({}), row({{"snr", "50"}, {"rmse_mean", "4.6"}, {"rmse_sd", "0.07"}}),
                  row({{"code", "mip"}, {"rmse_mean", "2.117"}, {"predicted_rmse", "2.1166"}}),
                  row({{"code", "mip"}, {"snr", "50"}})});
}

TEST(CampaignTable, ShowsTheSettingsThatVaryAndCaptionsTheRest) {
  const std::vector<std::string> lines = test::lines_of(table(two_by_two()));
  ASSERT_EQ(lines.size(), 8u);
  EXPECT_EQ(lines[0],
            "Fixed settings: image = data/camera.png, mode = numerical, velocity = 1, dt = 1, "
            "read\\_noise = 0, restoration = inverse, noise = poisson, rmse\\_margin = -1; 20 "
            "trials a setting; mean ± standard error (SE: sample sd / √trials).");
  EXPECT_EQ(lines[1], "");
  EXPECT_EQ(lines[2], "| code | snr | RMSE (mean ± SE) | predicted RMSE | RMSE\\_CI (mean ± SE) |");
  EXPECT_EQ(lines[3], "|---|---:|---:|---:|---:|");
  // SE = 0.0139 / sqrt(20) = 0.003108: 0.0031, the mean and the prediction to
  // the same place.
  EXPECT_EQ(lines[4], "| raskar | 100 | 2.3543 ± 0.0031 | 2.3505 | 2.5341 ± 0.0015 |");
  EXPECT_EQ(lines[5], "| raskar | 50 | 4.600 ± 0.016 | 2.350 | 2.5341 ± 0.0015 |");
  EXPECT_EQ(lines[6], "| mip | 100 | 2.1170 ± 0.0031 | 2.1166 | 2.5341 ± 0.0015 |");
}

TEST(CampaignTable, ARestoreVelocityOfItsOwnIsASetting) {
  const std::string text = table(results({row({}), row({{"restore_velocity", "1.05"}})}));
  EXPECT_NE(text.find("| restore\\_velocity |"), std::string::npos) << text;
  EXPECT_NE(text.find("| 1.05 |"), std::string::npos) << text;
  // Equal to the velocity in every row, it is neither a column nor in the caption.
  EXPECT_EQ(table(two_by_two()).find("restore"), std::string::npos);
}

TEST(CampaignTable, RoundsTheStandardErrorToItsDigitsAndTheMeanToItsPlace) {
  using table_numbers::round_mean_se;
  const auto text = [](double mean, double se, int digits) {
    const table_numbers::MeanSe r = round_mean_se(mean, se, digits);
    return r.mean.mantissa + " ± " + r.se.mantissa + " e" + std::to_string(r.mean.exponent);
  };
  EXPECT_EQ(text(2.354321, 0.003108, 2), "2.3543 ± 0.0031 e0");
  EXPECT_EQ(text(2.354321, 0.003108, 1), "2.354 ± 0.003 e0");
  EXPECT_EQ(text(2.354321, 0.003108, 3), "2.35432 ± 0.00311 e0");
  EXPECT_EQ(text(1.23456, 0.0996, 2), "1.23 ± 0.10 e0");       // 0.0996 rounds up a place
  EXPECT_EQ(text(12345.6, 123.0, 2), "12350 ± 120 e0");        // to the tens
  EXPECT_EQ(text(-0.00004, 0.0031, 2), "0.0000 ± 0.0031 e0");  // no "-0"
  EXPECT_EQ(text(1.2345678e14, 3.1e12, 2), "1.235 ± 0.031 e14");
  EXPECT_EQ(text(2.5e-5, 1.23e-6, 2), "2.50 ± 0.12 e-5");
  EXPECT_EQ(table_numbers::round_significant(84.93218, 4).mantissa, "84.93");
  EXPECT_EQ(table_numbers::round_significant(52.0, 4).mantissa, "52");
  const table_numbers::Rounded big = table_numbers::round_significant(9.99996e6, 4);
  EXPECT_EQ(big.mantissa + " e" + std::to_string(big.exponent), "1.000 e7");
  EXPECT_EQ(table_numbers::round_to_place(HUGE_VAL, -3).mantissa, "inf");
  // Extremes: finite text, never "nan" nor "inf", whatever the magnitudes.
  for (const double mean : {0.0, 1e-320, 5e-310, 1e300, -1.7e308}) {
    for (const double se : {4.9e-324, 1e-305, 1e-3, 1e290}) {
      const table_numbers::MeanSe r = round_mean_se(mean, se, 2);
      for (const std::string& text : {r.mean.mantissa, r.se.mantissa}) {
        EXPECT_EQ(text.find_first_not_of("-0123456789."), std::string::npos) << mean << " " << se;
      }
    }
  }
  EXPECT_FALSE(table_numbers::parse_number("nan"));
  EXPECT_FALSE(table_numbers::parse_number(""));
  EXPECT_FALSE(table_numbers::parse_number("1.5x"));
  EXPECT_EQ(*table_numbers::parse_number("-inf"), -HUGE_VAL);
}

TEST(CampaignTable, LargeNumbersInEachFormat) {
  const std::string csv = results({row({{"code", "accumulation"},
                                        {"rmse_mean", "1.2345678e14"},
                                        {"rmse_sd", "1.3864e13"},
                                        {"predicted_rmse", "inf"},
                                        {"status", "not-invertible"}})});
  const std::vector<std::string> columns = {"code", "rmse_mean", "predicted_rmse"};
  EXPECT_NE(table(csv, TableFormat::kMarkdown, columns)
                .find("| accumulation | (1.235 ± 0.031) × 10¹⁴ | ∞ | not-invertible |"),
            std::string::npos);
  EXPECT_NE(table(csv, TableFormat::kLatex, columns)
                .find("accumulation & $(1.235 \\pm 0.031) \\times 10^{14}$ & $\\infty$ & "
                      "not-invertible \\\\"),
            std::string::npos);
  EXPECT_EQ(table(csv, TableFormat::kCsv, columns),
            "code,rmse_mean,rmse_se,predicted_rmse,status\n"
            "accumulation,1.235e14,0.031e14,inf,not-invertible\n");
}

TEST(CampaignTable, RowsThatDidNotRunShowTheirStatus) {
  const std::string csv = results({row({}), row({{"code", "mip"},
                                                 {"rmse_mean", ""},
                                                 {"rmse_sd", ""},
                                                 {"rmse_ci_mean", ""},
                                                 {"rmse_ci_sd", ""},
                                                 {"predicted_rmse", ""},
                                                 {"status", "too-narrow"}})});
  const std::string text = table(csv);
  EXPECT_NE(text.find("| code | RMSE (mean ± SE) | predicted RMSE | RMSE\\_CI (mean ± SE) | "
                      "status |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("| mip | — | — | — | too-narrow |"), std::string::npos) << text;
  EXPECT_NE(table(csv, TableFormat::kLatex).find("mip & --- & --- & --- & too-narrow \\\\"),
            std::string::npos);
  EXPECT_NE(table(csv, TableFormat::kCsv).find("\nmip,,,,,,too-narrow\n"), std::string::npos);
  // Every row ok: no status column.
  EXPECT_EQ(table(two_by_two()).find("status"), std::string::npos);
}

TEST(CampaignTable, OneTrialHasNoStandardError) {
  const std::string text =
      table(results({row({{"trials", "1"}, {"rmse_sd", ""}}),
                     row({{"code", "mip"}, {"trials", "1"}, {"rmse_sd", ""}})}),
            TableFormat::kMarkdown, {"code", "rmse_mean", "predicted_rmse"});
  EXPECT_NE(text.find("1 trial a setting"), std::string::npos) << text;
  EXPECT_NE(text.find("| raskar | 2.354 | 2.350 |"), std::string::npos) << text;
  EXPECT_EQ(text.find("±"), std::string::npos) << text;
}

TEST(CampaignTable, VelocityDistributionsShowTheMse) {
  const std::string csv = results({row({{"velocity", ""},
                                        {"restore_velocity", ""},
                                        {"velocity_distribution", "uniform:0.5:1.5"},
                                        {"mse_mean", "4.06"},
                                        {"mse_sd", "0.74"},
                                        {"predicted_mse", "4.46"}}),
                                   row({{"velocity", ""},
                                        {"restore_velocity", ""},
                                        {"velocity_distribution", "normal:1:0.2"},
                                        {"mse_mean", "5.1"},
                                        {"mse_sd", "1.24"},
                                        {"predicted_mse", "5.28"}})},
                                  true);
  const std::string text = table(csv);
  EXPECT_NE(text.find("| velocity\\_distribution | MSE (mean ± SE) | predicted MSE | RMSE\\_CI "
                      "(mean ± SE) |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("| uniform:0.5:1.5 | 4.06 ± 0.17 | 4.46 |"), std::string::npos) << text;
  EXPECT_NE(text.find("| normal:1:0.2 | 5.10 ± 0.28 | 5.28 |"), std::string::npos) << text;
}

TEST(CampaignTable, EscapesTextForEachFormat) {
  const std::string csv =
      results({row({{"code", "a_b%c&d#e|f,g\"h"}}), row({{"code", "x~y^z\\w{}$"}})});
  const std::vector<std::string> columns = {"code", "rmse_mean"};
  EXPECT_NE(table(csv, TableFormat::kLatex, columns).find("a\\_b\\%c\\&d\\#e\\textbar{}f,g\"h & "),
            std::string::npos);
  EXPECT_NE(table(csv, TableFormat::kLatex, columns)
                .find("x\\textasciitilde{}y\\textasciicircum{}z\\textbackslash{}w\\{\\}\\$ & "),
            std::string::npos);
  EXPECT_NE(table(csv, TableFormat::kMarkdown, columns).find("| a\\_b%c&d#e\\|f,g\"h |"),
            std::string::npos);
  EXPECT_NE(table(csv, TableFormat::kCsv, columns).find("\n\"a_b%c&d#e|f,g\"\"h\",2.3543,"),
            std::string::npos);
}

TEST(CampaignTable, LatexIsABooktabsTabular) {
  const std::string text = table(two_by_two(), TableFormat::kLatex);
  const std::vector<std::string> lines = test::lines_of(text);
  ASSERT_EQ(lines.size(), 12u);
  EXPECT_EQ(lines[0], "% fssim campaign table: a booktabs tabular (\\usepackage{booktabs})");
  EXPECT_EQ(lines[1].rfind("% Fixed settings: image = data/camera.png", 0), 0u);
  EXPECT_EQ(lines[2], "\\begin{tabular}{lrrrr}");
  EXPECT_EQ(lines[3], "\\toprule");
  EXPECT_EQ(
      lines[4],
      "code & snr & RMSE (mean $\\pm$ SE) & predicted RMSE & RMSE\\_CI (mean $\\pm$ SE) \\\\");
  EXPECT_EQ(lines[5], "\\midrule");
  EXPECT_EQ(lines[6], "raskar & 100 & $2.3543 \\pm 0.0031$ & $2.3505$ & $2.5341 \\pm 0.0015$ \\\\");
  EXPECT_EQ(lines[10], "\\bottomrule");
  EXPECT_EQ(lines[11], "\\end{tabular}");
}

TEST(CampaignTable, ColumnsAsAskedInTheirOrder) {
  EXPECT_EQ(table(two_by_two(), TableFormat::kCsv, {"snr", "code", "rmse_mean", "blur_length"}, 3),
            "snr,code,rmse_mean,rmse_se,blur_length\n"
            "100,raskar,2.35432,0.00311,52\n"
            "50,raskar,4.6000,0.0157,52\n"
            "100,mip,2.11700,0.00311,52\n"
            "50,mip,2.35432,0.00311,52\n");
}

TEST(CampaignTable, SameInputSameBytes) {
  for (const TableFormat format :
       {TableFormat::kMarkdown, TableFormat::kLatex, TableFormat::kCsv}) {
    EXPECT_EQ(table(two_by_two(), format), table(two_by_two(), format));
  }
}

TEST(CampaignTable, RefusesWhatIsNoTableOfResults) {
  const auto refused = [](const std::string& csv, std::vector<std::string> columns, int digits,
                          std::initializer_list<std::string_view> words) {
    return test::throws_error([&] { table(csv, TableFormat::kMarkdown, columns, digits); },
                              ErrorKind::kUsage, words);
  };
  EXPECT_TRUE(refused("a,b\n1,2\n", {}, 2, {"results.csv", "no column 'status'"}));
  EXPECT_TRUE(refused("", {}, 2, {"results.csv"}));
  EXPECT_TRUE(refused(results({}), {}, 2, {"no rows"}));
  EXPECT_TRUE(refused(results({row({})}) + "1,2\n", {}, 2, {"results.csv"}));
  EXPECT_TRUE(refused(two_by_two(), {"rmse"}, 2, {"'rmse'", "not a column"}));
  EXPECT_TRUE(refused(two_by_two(), {"code", "snr", "code"}, 2, {"'code'", "twice"}));
  EXPECT_TRUE(refused(two_by_two(), {"mse_mean"}, 2, {"has no column 'mse_mean'"}));
  EXPECT_TRUE(refused(two_by_two(), {}, 0, {"digits 0", "[1, 6]"}));
  EXPECT_TRUE(refused(two_by_two(), {}, 7, {"digits 7", "[1, 6]"}));
  EXPECT_FALSE(table_format_from_string("html"));
  EXPECT_EQ(table_format_from_string("latex"), TableFormat::kLatex);
}

TEST(CampaignTable, AFileIsReadBounded) {
  test::TempDir dir;
  test::write_file(dir / "results.csv", two_by_two());
  EXPECT_EQ(campaign_table_file((dir / "results.csv").string(), {}), table(two_by_two()));
  EXPECT_TRUE(test::throws_error([&] { campaign_table_file((dir / "none.csv").string(), {}); },
                                 ErrorKind::kRuntime, {"results file", "none.csv"}));
}

}  // namespace
}  // namespace fss
