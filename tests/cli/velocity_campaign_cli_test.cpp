// `fssim campaign` with velocity distributions, end to end (docs/campaign.md, docs/method.md §13):
// each row is the simulator's run of its setting, the refusals are one line, `campaign check
// --predicted` compares the trials' mean MSE with E[MSE], and the axis merges and draws.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
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

// A width x height crop of data/camera.png, written into `dir`.
std::string write_crop(const fs::path& dir, int width, int height) {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) crop.at(0, y, x) = camera.at(0, 260 + y, 160 + x);
  }
  const auto png = encode_png8(crop);
  const fs::path path = dir / "crop.png";
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

// The rows of a CSV file as maps from column to cell.
std::vector<std::map<std::string, std::string>> csv_records(const fs::path& path) {
  const auto rows = parse_csv(test::read_file(path), path.string());
  std::vector<std::map<std::string, std::string>> records;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    std::map<std::string, std::string> record;
    for (std::size_t i = 0; i < rows[0].size(); ++i) record[rows[0][i]] = rows[r][i];
    records.push_back(record);
  }
  return records;
}

class VelocityCampaignCli : public ::testing::Test {
 protected:
  void SetUp() override {
    image_ = write_crop(tmp_.path(), 128, 24);
    test::write_file(tmp_ / "short.txt", "1 0 1 1 0 0 1 1\n");
    test::write_file(tmp_ / "v.txt", "0.8 1\n1.2 2\n");
    code_ = (tmp_ / "short.txt").string();
    base_ = "campaign --no-progress --threads 1 -i " + quote(image_) + " -c " + quote(code_);
  }

  // A refused command: exit 2 (usage) or 1 (a file), one line on stderr holding each of `parts`,
  // and no output directory.
  void ExpectRefused(const std::string& arguments, int exit_code,
                     const std::vector<std::string>& parts) {
    const fs::path out = tmp_ / "refused";
    const auto r = run_fssim(arguments + " -o " + quote(out));
    EXPECT_EQ(r.exit_code, exit_code) << arguments << "\n" << r.err;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    for (const std::string& part : parts) {
      EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in: " << r.err;
    }
    EXPECT_FALSE(fs::exists(out)) << arguments;
  }

  test::TempDir tmp_;
  std::string image_, code_, base_;
};

// Each row is `fssim --input` of its setting with its seed: the same mean and sd of the trials'
// MSE, E[MSE] and trial velocities in report.json.
TEST_F(VelocityCampaignCli, EachRowIsTheSimulatorsRunOfItsSetting) {
  const fs::path dir = tmp_ / "c";
  const auto r = run_fssim(base_ + " --snr 80 --trials 4 --per-trial --velocity-distribution " +
                           "uniform:0.6:1.4 " + quote(tmp_ / "v.txt") + " -o " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = csv_records(dir / "results.csv");
  const auto trials = csv_records(dir / "trials.csv");
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(trials.size(), 8u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    ASSERT_EQ(row.at("status"), "ok") << row.at("message");
    EXPECT_EQ(row.at("velocity"), "");
    const fs::path sim = tmp_ / ("sim" + std::to_string(i));
    const auto run = run_fssim("--input " + quote(image_) + " -c " + quote(code_) +
                               " --no-plots --snr 80 --trials 4 --seed " + row.at("seed") +
                               " --velocity-distribution " +
                               quote(row.at("velocity_distribution")) + " -o " + quote(sim));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto report = nlohmann::json::parse(test::read_file(sim / "report.json"));
    EXPECT_EQ(std::stod(row.at("mse_mean")), report["trials"]["mse_mean"].get<double>());
    EXPECT_EQ(std::stod(row.at("mse_sd")), report["trials"]["mse_sd"].get<double>());
    EXPECT_EQ(std::stod(row.at("predicted_mse")), report["prediction"]["mse"].get<double>());
    EXPECT_EQ(std::stod(row.at("predicted_rmse")), report["prediction"]["rmse"].get<double>());
    EXPECT_EQ(std::stod(row.at("rmse_mean")), report["trials"]["rmse_mean"].get<double>());
    const nlohmann::json& velocities = report["trials"]["velocities"];
    ASSERT_EQ(velocities.size(), 4u) << report["trials"].dump();
    for (std::size_t t = 0; t < 4; ++t) {
      const auto& trial = trials[4 * i + t];
      EXPECT_EQ(trial.at("velocity_distribution"), row.at("velocity_distribution"));
      EXPECT_EQ(std::stod(trial.at("trial_velocity")), velocities[t].get<double>()) << t;
    }
  }
}

TEST_F(VelocityCampaignCli, RefusesBadInputWithOneLine) {
  const std::string option = "--velocity-distribution";
  ExpectRefused(base_ + " -v 1 " + option + " uniform:0.5:1.5", 2,
                {"--velocity and --velocity-distribution", "not both"});
  ExpectRefused(base_ + " " + option + " uniform:1.5:0.5", 2,
                {"--velocity-distribution / \"velocity_distribution\"", "uniform:1.5:0.5"});
  ExpectRefused(base_ + " " + option + " " + quote(tmp_ / "nothing.txt"), 2,
                {"\"velocity_distribution\"", "nothing.txt", "neither"});
  test::write_file(tmp_ / "bad.txt", "0.5 1\n0.7\n");
  ExpectRefused(base_ + " " + option + " " + quote(tmp_ / "bad.txt"), 1,
                {"\"velocity_distribution\"", "bad.txt", "line 2"});
  ExpectRefused(base_ + " " + option + " uniform:0.5:1.5 --restoration wiener", 2,
                {"uniform:0.5:1.5", "wiener"});
  // The campaign file: the file, the key and the value named.
  test::write_file(tmp_ / "c.json", "{\"input\": " + nlohmann::json(image_).dump() +
                                        ", \"code\": " + nlohmann::json(code_).dump() +
                                        ", \"velocity_distribution\": [\"normal:1:0.2:2:1\"]}");
  ExpectRefused("campaign -f " + quote(tmp_ / "c.json"), 2,
                {"campaign file '", "c.json'", "\"velocity_distribution\"", "normal:1:0.2:2:1"});
  test::write_file(tmp_ / "both.json",
                   "{\"velocity\": \"1,2\", \"velocity_distribution\": \"uniform:0.5:1\"}");
  ExpectRefused("campaign -f " + quote(tmp_ / "both.json"), 2,
                {"both.json", "'velocity' and 'velocity_distribution'"});
  // campaign check --predicted: no EXPECTED.csv, and no --exact.
  const fs::path results = tmp_ / "r.csv";
  test::write_file(results,
                   "code,trials,rmse_mean,rmse_sd,predicted_rmse,status\nx,2,1,0.1,1,ok\n");
  for (const auto& [arguments, part] : std::vector<std::pair<std::string, std::string>>{
           {" --predicted --k-se 3 " + quote(results), "give no EXPECTED.csv"},
           {" --predicted --exact", "--exact compares the exact columns of EXPECTED.csv"},
           {"", "needs EXPECTED.csv (or --predicted)"}}) {
    const auto r = run_fssim("campaign check " + quote(results) + arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << r.err;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
  }
}

// On the command line, either axis replaces the campaign file's velocity axis.
TEST_F(VelocityCampaignCli, TheCommandLineReplacesTheFilesVelocityAxis) {
  test::write_file(tmp_ / "c.json", "{\"input\": " + nlohmann::json(image_).dump() +
                                        ", \"code\": " + nlohmann::json(code_).dump() +
                                        ", \"velocity\": \"0.9,1.1\", \"trials\": 2}");
  const auto distribution =
      run_fssim("campaign --no-progress -f " + quote(tmp_ / "c.json") +
                " --velocity-distribution uniform:0.8:1.2 -o " + quote(tmp_ / "d"));
  ASSERT_EQ(distribution.exit_code, 0) << distribution.err;
  const auto rows = csv_records(tmp_ / "d" / "results.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("velocity_distribution"), "uniform:0.8:1.2");
  test::write_file(tmp_ / "d.json", "{\"input\": " + nlohmann::json(image_).dump() +
                                        ", \"code\": " + nlohmann::json(code_).dump() +
                                        ", \"velocity_distribution\": \"uniform:0.8:1.2\"}");
  const auto velocity = run_fssim("campaign --no-progress -f " + quote(tmp_ / "d.json") +
                                  " -v 0.9,1.1 -o " + quote(tmp_ / "v"));
  ASSERT_EQ(velocity.exit_code, 0) << velocity.err;
  const auto plain = csv_records(tmp_ / "v" / "results.csv");
  ASSERT_EQ(plain.size(), 2u);
  EXPECT_EQ(plain[1].at("velocity"), "1.1");
  EXPECT_EQ(plain[1].count("velocity_distribution"), 0u);
}

// campaign check --predicted passes a campaign under distributions (each setting's own seeds,
// z within 4 over the family of 4 settings) and fails the same results with E[MSE] 25 % off (the
// trials' MSE varies with the velocity: its sd is 0.4 to 0.8 times its mean here).
TEST_F(VelocityCampaignCli, CheckComparesTheTrialsWithThePrediction) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "Monte Carlo: run in the Release suite";
  const fs::path dir = tmp_ / "c";
  const auto r = run_fssim(base_ + " --snr 30,100 --trials 300 --seed 3 --figures " +
                           "--velocity-distribution uniform:0.8:1.0 normal:1:0.1 -o " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string results = quote(dir / "results.csv");
  const auto check = run_fssim("campaign check --predicted --k-se 4 " + results + " --junit " +
                               quote(tmp_ / "junit.xml"));
  EXPECT_EQ(check.exit_code, 0) << check.out;
  EXPECT_NE(check.out.find("campaign check: 4 comparisons, 0 deviations"), std::string::npos)
      << check.out;
  EXPECT_NE(test::read_file(tmp_ / "junit.xml").find("tests=\"4\" failures=\"0\""),
            std::string::npos);
  // The prediction 25 % off: a deviation per row.
  auto rows = parse_csv(test::read_file(dir / "results.csv"), "results.csv");
  std::size_t column = 0;
  while (rows[0][column] != "predicted_mse") ++column;
  std::string scaled;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i > 0) rows[i][column] = std::to_string(1.25 * std::stod(rows[i][column]));
    for (std::size_t j = 0; j < rows[i].size(); ++j) {
      scaled += (j ? "," : "") + nlohmann::json(rows[i][j]).dump();
    }
    scaled += "\n";
  }
  test::write_file(tmp_ / "scaled.csv", scaled);
  const auto off = run_fssim("campaign check --predicted --k-se 4 " + quote(tmp_ / "scaled.csv"));
  EXPECT_EQ(off.exit_code, 1) << off.out;
  EXPECT_NE(off.out.find("4 comparisons, 4 deviations"), std::string::npos) << off.out;
  // The figures: sqrt(mean MSE) against snr, one per distribution.
  const fs::path normal = dir / "figures" / "rmse_vs_snr__crop__numerical__v-normal-1-0.1";
  EXPECT_TRUE(fs::exists(dir / "figures" / "rmse_vs_snr__crop__numerical__v-uniform-0.8-1.svg"));
  EXPECT_TRUE(fs::exists(normal.string() + ".png"));
  EXPECT_NE(test::read_file(normal.string() + ".svg").find("v ~ normal:1:0.1"), std::string::npos);
}

// Shards of a campaign under distributions merge into the bytes of one run.
TEST_F(VelocityCampaignCli, ShardsMergeIntoTheBytesOfOneRun) {
  const std::string args = base_ + " --snr 60,120 --trials 2 --per-trial " +
                           "--velocity-distribution normal:1:0.1 " + quote(tmp_ / "v.txt");
  ASSERT_EQ(run_fssim(args + " -o " + quote(tmp_ / "one")).exit_code, 0);
  for (const char* shard : {"1/3", "2/3", "3/3"}) {
    const auto r = run_fssim(args + " --shard " + shard + " -o " +
                             quote(tmp_ / ("part" + std::string(1, shard[0]))));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const auto merge =
      run_fssim("campaign merge -o " + quote(tmp_ / "m") + " " + quote(tmp_ / "part1") + " " +
                quote(tmp_ / "part2") + " " + quote(tmp_ / "part3"));
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  for (const char* name : {"results.csv", "results.jsonl", "trials.csv", "trials.jsonl",
                           "campaign.json", "journal.jsonl"}) {
    EXPECT_EQ(test::read_file(tmp_ / "m" / name), test::read_file(tmp_ / "one" / name)) << name;
  }
  EXPECT_EQ(nlohmann::json::parse(test::read_file(tmp_ / "m" / "campaign.json"))["schema_version"],
            4);
}

}  // namespace
}  // namespace fss
