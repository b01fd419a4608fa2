// No setting lost without a word: `--rmse-margin auto` (the campaigns' default) runs what the
// paper's margin cannot, settings that still cannot run are listed on stderr and make the exit
// status 1 (unless --skip-unrunnable), settings that do not apply are listed and never fail,
// shards exit 0 and their merge reports; the simulator and sweep take `--rmse-margin auto`.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fss/campaign/check.h"
#include "fss/campaign/gaps.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;
using ::testing::HasSubstr;
using ::testing::Not;

// raskar (L = 52) on a 600-wide strip: v 1 fits the paper's margin (9B + 1 = 469), v 1.5 needs
// auto (B = 78: 5B + 1 = 391 <= 600 < 703), v 2.5 cannot run (B = 130: 5B + 1 = 651 > 600).
class CampaignGaps : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto png = encode_png8(test::make_test_image(600, 6, 1));
    image_ = tmp_ / "strip.png";
    test::write_file(image_, std::string(png.begin(), png.end()));
    base_ = "campaign --no-progress --threads 1 --trials 2 -i " + quote(image_) + " -c raskar";
  }
  // The rows of DIR/results.csv by column name, header excluded.
  std::vector<std::string> column(const fs::path& dir, const std::string& name) {
    const auto rows = parse_csv(test::read_file(dir / "results.csv"), "results.csv");
    std::vector<std::string> cells;
    const auto at = std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin();
    for (std::size_t i = 1; i < rows.size(); ++i) cells.push_back(rows[i][at]);
    return cells;
  }
  test::TempDir tmp_;
  fs::path image_;
  std::string base_;
};

TEST_F(CampaignGaps, AutoMarginRunsWhatThePapersMarginCannot) {
  const auto r = run_fssim(base_ + " -v 1,1.5 -o " + quote(tmp_ / "auto"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(column(tmp_ / "auto", "status"), (std::vector<std::string>{"ok", "ok"}));
  EXPECT_EQ(column(tmp_ / "auto", "rmse_margin"), (std::vector<std::string>{"156", "144"}));
  // The paper's margin refuses v 1.5 and keeps every number of v 1.
  const auto strict = run_fssim(base_ + " -v 1,1.5 --rmse-margin -1 -o " + quote(tmp_ / "3b"));
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_EQ(column(tmp_ / "3b", "status"), (std::vector<std::string>{"ok", "too-narrow"}));
  EXPECT_EQ(column(tmp_ / "3b", "rmse_mean")[0], column(tmp_ / "auto", "rmse_mean")[0]);
  EXPECT_EQ(column(tmp_ / "3b", "seed"), column(tmp_ / "auto", "seed"));
}

TEST_F(CampaignGaps, SettingsThatCannotRunAreListedAndFailTheCampaign) {
  const auto r = run_fssim(base_ + " -v 1,2.5 --snr 50,100 -o " + quote(tmp_ / "c"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("fssim: campaign: 2 of 4 settings cannot run"));
  EXPECT_THAT(r.err, HasSubstr("needs a width of at least 651 (5B + 1)"));
  EXPECT_THAT(r.err, HasSubstr("fssim: campaign:     code=raskar velocity=2.5 snr=50\n"));
  EXPECT_THAT(r.err, HasSubstr("fssim: campaign:     code=raskar velocity=2.5 snr=100\n"));
  EXPECT_THAT(r.err, HasSubstr("fssim: error: 2 settings cannot run"));
  // Every result file is written, the settings that ran included.
  EXPECT_EQ(column(tmp_ / "c", "status"),
            (std::vector<std::string>{"ok", "ok", "too-narrow", "too-narrow"}));
  // Accepted on request: still listed, exit 0, the same files.
  const auto skipped =
      run_fssim(base_ + " -v 1,2.5 --snr 50,100 --skip-unrunnable -o " + quote(tmp_ / "s"));
  EXPECT_EQ(skipped.exit_code, 0) << skipped.err;
  EXPECT_THAT(skipped.err, HasSubstr("2 of 4 settings cannot run"));
  EXPECT_THAT(skipped.err, Not(HasSubstr("error")));
  EXPECT_EQ(test::read_file(tmp_ / "s" / "results.csv"),
            test::read_file(tmp_ / "c" / "results.csv"));
}

TEST_F(CampaignGaps, SettingsThatDoNotApplyAreListedAndDoNotFail) {
  const auto r = run_fssim(base_ + " mip -m numerical analog -o " + quote(tmp_ / "c"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("fssim: campaign: 1 of 4 settings do not apply"));
  EXPECT_THAT(r.err, HasSubstr("cannot be used in analog mode"));
  EXPECT_THAT(r.err, HasSubstr("(1 settings)"));
  EXPECT_THAT(r.err, Not(HasSubstr("cannot run")));
}

TEST_F(CampaignGaps, ShardsRecordAndTheMergeReports) {
  const std::string args = base_ + " -v 1,2.5 --snr 50,100";
  for (const char* shard : {"1", "2"}) {
    const auto r = run_fssim(args + " --shard " + shard + "/2 -o " +
                             quote(tmp_ / (std::string("part") + shard)));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("cannot run"));
    EXPECT_THAT(r.err, HasSubstr("'campaign merge' lists them again"));
  }
  const std::string parts = quote(tmp_ / "part1") + " " + quote(tmp_ / "part2");
  const auto merged = run_fssim("campaign merge -o " + quote(tmp_ / "m") + " " + parts);
  EXPECT_EQ(merged.exit_code, 1);
  EXPECT_THAT(merged.err, HasSubstr("fssim: campaign merge: 2 of 4 settings cannot run"));
  EXPECT_THAT(merged.err, HasSubstr("fssim: error: 2 settings cannot run"));
  const auto accepted =
      run_fssim("campaign merge --skip-unrunnable -o " + quote(tmp_ / "m2") + " " + parts);
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;
  const auto single = run_fssim(args + " --skip-unrunnable -o " + quote(tmp_ / "one"));
  EXPECT_EQ(test::read_file(tmp_ / "m2" / "results.csv"),
            test::read_file(tmp_ / "one" / "results.csv"));
}

TEST_F(CampaignGaps, TheCampaignFileTakesAuto) {
  const fs::path file = tmp_ / "c.json";
  test::write_file(file, "{\"velocity\": [1.5], \"rmse_margin\": \"auto\"}");
  const auto r = run_fssim(base_ + " -f " + quote(file) + " -o " + quote(tmp_ / "f"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(column(tmp_ / "f", "rmse_margin"), std::vector<std::string>{"144"});
  test::write_file(file, "{\"rmse_margin\": \"wide\"}");
  const auto bad = run_fssim(base_ + " -f " + quote(file) + " -o " + quote(tmp_ / "g"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(test::lines_of(bad.err).size(), 1u) << bad.err;
  EXPECT_THAT(bad.err, HasSubstr("rmse_margin"));
  const auto flag = run_fssim(base_ + " --rmse-margin wide -o " + quote(tmp_ / "h"));
  EXPECT_EQ(flag.exit_code, 2);
  EXPECT_THAT(flag.err, HasSubstr("--rmse-margin"));
  EXPECT_FALSE(fs::exists(tmp_ / "g"));
  EXPECT_FALSE(fs::exists(tmp_ / "h"));
}

TEST_F(CampaignGaps, TheSimulatorAndSweepTakeAuto) {
  const std::string input = " --input " + quote(image_) + " --velocity 1.5 --seed 2";
  const auto paper = run_fssim(input + " --outdir " + quote(tmp_ / "p"));
  EXPECT_EQ(paper.exit_code, 2);
  EXPECT_THAT(paper.err, HasSubstr("--rmse-margin auto"));
  const auto automatic =
      run_fssim(input + " --rmse-margin auto --no-plots --outdir " + quote(tmp_ / "a"));
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  EXPECT_THAT(automatic.err, HasSubstr("RMSE margin auto: 144 columns"));
  EXPECT_THAT(automatic.out, HasSubstr("RMSE columns [144, 222)"));
  const auto given =
      run_fssim(input + " --rmse-margin 144 --no-plots --outdir " + quote(tmp_ / "g"));
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_EQ(test::read_file(tmp_ / "a" / "restored.png"),
            test::read_file(tmp_ / "g" / "restored.png"));
  const auto sweep =
      run_fssim("sweep -i " + quote(image_) + " --noise none -v 1:1.5:0.5 --rmse-margin auto -o " +
                quote(tmp_ / "sweep.csv"));
  EXPECT_EQ(sweep.exit_code, 0) << sweep.err;
  const auto bad = run_fssim(input + " --rmse-margin -2 --outdir " + quote(tmp_ / "b"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(test::lines_of(bad.err).size(), 1u) << bad.err;
}

TEST(CampaignGapList, TellsTheSettingsApartByWhatVaries) {
  ResultRow ok(campaign_columns().size());
  const auto set = [](ResultRow& row, const char* name, const std::string& value) {
    row[campaign_column_index(name)] = value;
  };
  set(ok, "image", "a/b/img.png");
  set(ok, "code", "raskar");
  set(ok, "velocity", "1");
  set(ok, "restore_velocity", "1");
  set(ok, "snr", "100");
  set(ok, "status", "ok");
  ResultRow narrow = ok;
  set(narrow, "velocity", "3");
  set(narrow, "restore_velocity", "3");
  set(narrow, "status", "too-narrow");
  set(narrow, "message", "too narrow");
  const std::vector<CampaignGap> gaps = campaign_gaps({ok, narrow});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].kind, GapKind::kCannotRun);
  EXPECT_EQ(gaps[0].setting, "code=raskar velocity=3");
  std::vector<ResultRow> many(30, narrow);
  for (int i = 0; i < 30; ++i) set(many[i], "snr", std::to_string(i + 1));
  const std::vector<std::string> lines = gap_report_lines(campaign_gaps(many), 30, 5);
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(lines[0],
            "30 of 30 settings cannot run (status too-narrow, invalid or failed in "
            "results.csv):");
  EXPECT_EQ(lines[1], "  too narrow:");
  EXPECT_EQ(lines[2], "    code=raskar snr=1");
  EXPECT_EQ(lines[6], "  ... and 26 more settings");
}

}  // namespace
}  // namespace fss
