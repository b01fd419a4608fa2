// `fssim campaign table` end to end: a small campaign's results as Markdown,
// LaTeX (compiled with booktabs when pdflatex is installed) and CSV, the same
// bytes on standard output and in a file, and one-line refusals.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;

class CampaignTableCli : public ::testing::Test {
 protected:
  // A 400 x 24 crop of camera.png, two codes at two snr values, 3 trials.
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const Image camera = read_png(test::source_path("data/camera.png"));
    Image crop(400, 24, 1);
    for (int y = 0; y < 24; ++y) {
      for (int x = 0; x < 400; ++x) crop.at(0, y, x) = camera.at(0, 200 + y, 50 + x);
    }
    const auto png = encode_png8(crop);
    test::write_file(*dir_ / "crop.png", std::string(png.begin(), png.end()));
    const test::CommandResult run =
        run_fssim("campaign --no-progress -i " + quote(*dir_ / "crop.png") +
                  " -c raskar sinc --velocity 0.5 --snr 50,100 --trials 3 --threads 1 -o " +
                  quote(*dir_ / "run"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    results_ = new std::string((*dir_ / "run" / "results.csv").string());
  }
  static void TearDownTestSuite() {
    delete results_;
    delete dir_;
  }
  static test::TempDir* dir_;
  static std::string* results_;
};
test::TempDir* CampaignTableCli::dir_ = nullptr;
std::string* CampaignTableCli::results_ = nullptr;

TEST_F(CampaignTableCli, MarkdownByDefault) {
  const test::CommandResult r = run_fssim("campaign table " + quote(*results_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::vector<std::string> lines = test::lines_of(r.out);
  ASSERT_EQ(lines.size(), 8u) << r.out;
  EXPECT_NE(lines[0].find("Fixed settings: image = "), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("velocity = 0.5"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("3 trials a setting"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[2], "| code | snr | RMSE (mean ± SE) | predicted RMSE | RMSE\\_CI (mean ± SE) |");
  EXPECT_EQ(lines[4].rfind("| raskar | 50 | ", 0), 0u) << lines[4];
  EXPECT_EQ(lines[7].rfind("| sinc | 100 | ", 0), 0u) << lines[7];
  EXPECT_NE(lines[7].find(" ± "), std::string::npos) << lines[7];
}

TEST_F(CampaignTableCli, AFileHoldsTheBytesOfStandardOutput) {
  for (const char* format : {"markdown", "latex", "csv"}) {
    const std::string args = "campaign table " + quote(*results_) + " --format " + format;
    const test::CommandResult out = run_fssim(args);
    ASSERT_EQ(out.exit_code, 0) << out.err;
    const fs::path file = *dir_ / (std::string("table.") + format);
    const test::CommandResult written = run_fssim(args + " -o " + quote(file));
    ASSERT_EQ(written.exit_code, 0) << written.err;
    EXPECT_EQ(written.out, "");
    EXPECT_EQ(test::read_file(file), out.out) << format;
    EXPECT_EQ(run_fssim(args).out, out.out) << format;  // the same bytes every time
  }
}

TEST_F(CampaignTableCli, CsvSplitsMeanAndStandardError) {
  const test::CommandResult r = run_fssim("campaign table " + quote(*results_) +
                                          " --format csv --columns code,snr,rmse_mean");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = test::lines_of(r.out);
  ASSERT_EQ(lines.size(), 5u) << r.out;
  EXPECT_EQ(lines[0], "code,snr,rmse_mean,rmse_se");
  EXPECT_EQ(lines[1].rfind("raskar,50,", 0), 0u) << lines[1];
}

// The LaTeX compiles in a document that loads booktabs (when pdflatex is
// installed: Debian's texlive-latex-recommended).
TEST_F(CampaignTableCli, LatexCompiles) {
  if (test::run_command("command -v pdflatex >/dev/null").exit_code != 0) {
    GTEST_SKIP() << "pdflatex is not installed";
  }
  const test::CommandResult r = run_fssim("campaign table " + quote(*results_) + " --format latex");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path tex = *dir_ / "doc.tex";
  test::write_file(tex, "\\documentclass{article}\n\\usepackage{booktabs}\n\\begin{document}\n" +
                            r.out + "\\end{document}\n");
  const test::CommandResult latex = test::run_command(
      "cd " + quote(dir_->path()) + " && pdflatex -interaction=nonstopmode -halt-on-error doc.tex");
  EXPECT_EQ(latex.exit_code, 0) << latex.out;
  EXPECT_TRUE(fs::exists(*dir_ / "doc.pdf"));
}

// -o naming RESULTS.csv itself, a hard link to it or a symbolic link to it
// is refused, and the results keep their bytes.
TEST_F(CampaignTableCli, NeverWritesOverItsResults) {
  const std::string bytes = test::read_file(*results_);
  const fs::path hard = *dir_ / "hard.csv", symbolic = *dir_ / "symbolic.csv";
  fs::remove(hard);
  fs::remove(symbolic);
  fs::create_hard_link(*results_, hard);
  fs::create_symlink(*results_, symbolic);
  for (const fs::path& output : {fs::path(*results_), hard, symbolic}) {
    const test::CommandResult r =
        run_fssim("campaign table " + quote(*results_) + " -o " + quote(output));
    EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << output;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_EQ(test::read_file(*results_), bytes) << output;
  }
}

TEST_F(CampaignTableCli, RefusalsAreOneLine) {
  const auto refused = [](const std::string& args, int status, const std::string& words) {
    const test::CommandResult r = run_fssim("campaign table " + args);
    EXPECT_EQ(r.exit_code, status) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << args << ": " << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << args << ": " << r.err;
  };
  refused(quote(*results_) + " --format html", 2,
          "--format 'html': expected markdown, latex or csv");
  refused(quote(*results_) + " --columns code,rmse", 2, "'rmse' is not a column");
  refused(quote(*results_) + " --columns mse_mean", 2, "has no column 'mse_mean'");
  refused(quote(*results_) + " --digits 0", 2, "--digits");
  refused(quote(*results_) + " -o " + quote(*results_), 2, "would replace the input");
  refused(quote(*dir_ / "run" / "campaign.json"), 2, "campaign.json");
  refused(quote(*dir_ / "crop.png"), 1, "not a text file");
  refused(quote(*dir_ / "missing.csv"), 1, "missing.csv");
  test::write_file(*dir_ / "other.csv", "a,b\n1,2\n");
  refused(quote(*dir_ / "other.csv"), 2, "not a campaign's results.csv");
  refused(quote(*results_) + " --velocity 2", 2, "--velocity");
}

}  // namespace
}  // namespace fss
