// `fssim campaign check` as a CI regression out of the box (docs/campaign.md, "Regression
// checks"): two seeds of one campaign pass with no option, a shift of half a gray level in the
// expected RMSE fails, exact columns compare within round-off (bitwise with --exact), a k-SE
// rule that cannot apply is refused, and the JUnit report names each setting.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fss/campaign/check.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;

// `rows` (parse_csv's) as CSV text.
std::string csv_text(const std::vector<std::vector<std::string>>& rows) {
  std::string text;
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) text += (i ? "," : "") + row[i];
    text += "\n";
  }
  return text;
}

// The file's rows with column `name` of every row but the header replaced by f(cell).
template <typename F>
std::string with_column(const fs::path& file, const std::string& name, F f) {
  auto rows = parse_csv(test::read_file(file), file.string());
  std::size_t column = 0;
  while (column < rows[0].size() && rows[0][column] != name) ++column;
  EXPECT_LT(column, rows[0].size()) << name;
  for (std::size_t r = 1; r < rows.size() && column < rows[0].size(); ++r) {
    rows[r][column] = f(rows[r][column]);
  }
  return csv_text(rows);
}

class CampaignCheckCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto png = encode_png8(test::make_test_image(600, 16, 1));
    test::write_file(image_, std::string(png.begin(), png.end()));
  }

  // Runs the campaign of 4 settings (2 codes x 2 snr values), `trials` trials, into tmp_/NAME;
  // returns its results.csv.
  fs::path Run(const std::string& name, int seed, int trials = 20) const {
    const auto r = run_fssim("campaign --no-progress -i " + quote(image_) +
                             " -c raskar snapshot --snr 50,200 --trials " + std::to_string(trials) +
                             " --seed " + std::to_string(seed) + " -o " + quote(tmp_ / name));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return tmp_ / name / "results.csv";
  }

  test::TempDir tmp_;
  fs::path image_ = tmp_ / "strip.png";
};

// Seeds 1 to 6 in pairs: each pair passes with no option (a false alarm has a chance below
// 0.1 % per check); the expected RMSE half a gray level higher fails on every row (half a gray
// level is 10 to 60 standard errors here).
TEST_F(CampaignCheckCli, TwoSeedsPassAndAHalfGrayLevelFails) {
  for (int seed = 1; seed <= 5; seed += 2) {
    const fs::path a = Run("a" + std::to_string(seed), seed);
    const fs::path b = Run("b" + std::to_string(seed), seed + 1);
    const auto check = run_fssim("campaign check " + quote(a) + " " + quote(b));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
    const std::vector<std::string> lines = test::lines_of(check.out);
    ASSERT_EQ(lines.size(), 5u) << check.out;
    EXPECT_EQ(lines[0].rfind("compared rmse_mean, rmse_ci_mean, ssim_mean: within k = ", 0), 0u)
        << lines[0];
    EXPECT_NE(lines[0].find("standard errors (Student-t, 19 degrees of freedom: a false alarm "
                            "among these 12 comparisons has a chance below 0.1 %), or rel 1e-09"),
              std::string::npos)
        << lines[0];
    EXPECT_EQ(lines[1].rfind("compared code_normalized_l1, blur_length, predicted_rmse, ", 0), 0u)
        << lines[1];
    EXPECT_EQ(lines[2], "compared predicted_exact, invertible, status: equal");
    EXPECT_EQ(lines[3], "left out psnr_mean: follows rmse_mean");
    EXPECT_EQ(lines[4].rfind("campaign check: ", 0), 0u);
    EXPECT_NE(lines[4].find(" comparisons, 0 deviations"), std::string::npos);
  }
  test::write_file(tmp_ / "shifted.csv",
                   with_column(tmp_ / "b1" / "results.csv", "rmse_mean", [](const std::string& v) {
                     return format_exact(std::stod(v) + 0.5);
                   }));
  const auto shifted =
      run_fssim("campaign check " + quote(tmp_ / "a1" / "results.csv") + " " +
                quote(tmp_ / "shifted.csv") + " --junit " + quote(tmp_ / "junit.xml"));
  EXPECT_EQ(shifted.exit_code, 1) << shifted.out << shifted.err;
  EXPECT_NE(shifted.out.find(" comparisons, 4 deviations"), std::string::npos) << shifted.out;
  // The JUnit report names each setting: its image, code and the snr that varies.
  const std::string xml = test::read_file(tmp_ / "junit.xml");
  for (const char* code : {"raskar", "snapshot"}) {
    for (const char* snr : {"50", "200"}) {
      const std::string name = "code=" + std::string(code) + " snr=" + snr + ": rmse_mean\"";
      EXPECT_NE(xml.find("<testcase classname=\"fssim campaign check.rmse_mean\" name=\"image="),
                std::string::npos);
      EXPECT_NE(xml.find(name + ">\n    <failure message="), std::string::npos) << name << xml;
      EXPECT_NE(xml.find("code=" + std::string(code) + " snr=" + snr + ": rmse_ci_mean\"/>"),
                std::string::npos)
          << xml;
    }
  }
}

// An exact output 1e-12 off (relative, as another processor's FFT may give) passes by default
// and fails with --exact.
TEST_F(CampaignCheckCli, ExactColumnsPassRoundOffUnlessExact) {
  const fs::path results = Run("r", 1, 3);
  test::write_file(tmp_ / "rounded.csv",
                   with_column(results, "predicted_rmse", [](const std::string& v) {
                     return format_exact(std::stod(v) * (1.0 + 1e-12));
                   }));
  const std::string args = "campaign check " + quote(results) + " " + quote(tmp_ / "rounded.csv");
  const auto by_default = run_fssim(args);
  EXPECT_EQ(by_default.exit_code, 0) << by_default.out;
  const auto exact = run_fssim(args + " --exact");
  EXPECT_EQ(exact.exit_code, 1) << exact.out;
  EXPECT_NE(exact.out.find(" comparisons, 4 deviations"), std::string::npos) << exact.out;
  EXPECT_NE(exact.out.find("predicted_rmse, predicted_rmse_noise_free"), std::string::npos);
  EXPECT_NE(exact.out.find(": equal\n"), std::string::npos) << exact.out;
  EXPECT_EQ(
      run_fssim("campaign check " + quote(results) + " " + quote(results) + " --exact").exit_code,
      0);
}

// A k-SE rule that cannot apply, given or by default, is refused in one line (exit 2) that says
// what it needs: an EXPECTED without rmse_sd, a campaign of one trial.
TEST_F(CampaignCheckCli, RefusesAStandardErrorItCannotApply) {
  const fs::path results = Run("r", 1, 3);
  test::write_file(tmp_ / "e.csv", "image,code,snr,rmse_mean\nstrip.png,raskar,50,4.7\n");
  const std::string expected = quote(tmp_ / "e.csv");
  for (const std::string& option : {std::string(" --k-se 4"), std::string()}) {
    const auto r = run_fssim("campaign check " + quote(results) + " " + expected + option);
    EXPECT_EQ(r.exit_code, 2) << option << r.out;
    ASSERT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("has no column 'rmse_sd'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rmse_sd and trials (2 or more) in both files"), std::string::npos);
    EXPECT_EQ(r.err.find("--k-se 4") != std::string::npos, !option.empty()) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  const fs::path one = Run("one", 2, 1);
  const auto r = run_fssim("campaign check " + quote(one) + " " + quote(results) + " --junit " +
                           quote(tmp_ / "junit.xml"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("has trials 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(2 or more)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp_ / "junit.xml"));
  // With a given tolerance the same files are compared.
  EXPECT_EQ(
      run_fssim("campaign check " + quote(one) + " " + quote(results) + " --abs 100").exit_code, 0);
}

}  // namespace
}  // namespace fss
