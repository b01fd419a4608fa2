// `fssim campaign` and `fssim sweep` with restorations, end to end: each row is the simulator's run
// of its setting, a campaign without restorations keeps the hash it had before them, the options
// that would be ignored are refused, and the restoration axis resumes and merges.
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
    for (int x = 0; x < width; ++x) crop.at(0, y, x) = camera.at(0, 200 + y, 150 + x);
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

// The simulator's options for a row's restoration (its restoration, regularization and prior).
std::string restoration_options(const std::map<std::string, std::string>& row) {
  std::string options = " --restoration " + row.at("restoration");
  if (!row.at("regularization").empty()) options += " --regularization " + row.at("regularization");
  if (!row.at("prior").empty()) options += " --prior " + row.at("prior");
  return options;
}

// The number the simulator printed after `label` ("Predicted RMSE: 2.345664 (...)").
double printed(const std::string& out, const std::string& label) {
  const std::size_t at = out.find(label);
  if (at == std::string::npos) return std::nan("");
  return std::stod(out.substr(at + label.size()));
}

class RestorationCampaignCli : public ::testing::Test {
 protected:
  void SetUp() override {
    image_ = write_crop(tmp_.path(), 160, 32);
    test::write_file(tmp_ / "short.txt", "1 0 1 1 0 0 1 1\n");
    code_ = (tmp_ / "short.txt").string();
    base_ = "campaign --no-progress --threads 1 -i " + quote(image_) + " -c " + quote(code_);
    axis_ =
        " --restoration inverse,tikhonov,wiener --regularization 0.01,optimal --prior "
        "power-law:1.5,oracle";
  }

  // Runs the simulator on the crop with `options` into a fresh directory; its report.json.
  nlohmann::json simulate(const std::string& options, std::string* out) {
    const fs::path dir = tmp_ / ("sim" + std::to_string(++runs_));
    const auto r = run_fssim("--input " + quote(image_) + " -c " + quote(code_) + " --no-plots " +
                             options + " -o " + quote(dir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (out != nullptr) *out = r.out;
    return nlohmann::json::parse(test::read_file(dir / "report.json"));
  }

  test::TempDir tmp_;
  std::string image_, code_, base_, axis_;
  int runs_ = 0;
};

// The hashes and seeds below were written by fssim before campaigns had restorations (the campaign
// code of commit 03b6a69, run in a directory holding data/camera.png as camera.png and
// short.txt): a campaign without restorations keeps them, so a journal it wrote still resumes.
// That campaign's margin was the paper's 3B, now `--rmse-margin -1` (auto is the default).
TEST_F(RestorationCampaignCli, ACampaignWithoutRestorationsKeepsItsHashAndSeeds) {
  fs::copy_file(test::source_path("data/camera.png"), tmp_ / "camera.png");
  const std::string in =
      "cd " + quote(tmp_.path()) + " && " + quote(FSSIM_BINARY_PATH) +
      " campaign --no-progress -i camera.png -c raskar short.txt --rmse-margin -1";
  const auto small = test::run_command(in + " -v 0.5,1 --snr 100 --trials 1 --seed 7 -o one");
  ASSERT_EQ(small.exit_code, 0) << small.err;
  const auto manifest = nlohmann::json::parse(test::read_file(tmp_ / "one" / "campaign.json"));
  EXPECT_EQ(manifest["campaign_sha256"],
            "14f70db1f03c511e38e41f39d3088d70000292ae87f9fa8d82b3a5df012d2219");
  std::vector<std::string> seeds;
  for (const auto& row : csv_records(tmp_ / "one" / "results.csv")) seeds.push_back(row.at("seed"));
  EXPECT_EQ(seeds, (std::vector<std::string>{"9021973240266528746", "2668546297376781646",
                                             "18130873372353148514", "9563653452887894670"}));
  // The inverse filter given explicitly is the same campaign.
  const auto inverse = test::run_command(
      in + " -v 0.5,1 --snr 100 --trials 1 --seed 7 --restoration inverse -o one");
  EXPECT_EQ(inverse.exit_code, 0) << inverse.err;
  EXPECT_NE(inverse.out.find("(0 run now, 4 from the journal)"), std::string::npos) << inverse.out;
  // Every axis and option but the restorations (one setting of 96 run: its shard).
  const auto wide = test::run_command(
      in +
      " -m numerical analog -v 0.5:1:0.5 --restore-velocity 0.5,1.5 --snr 50:200:x2 "
      "--trials 2 --seed 7 --read-noise 0,2 --per-trial --shard 1/96 -o wide");
  ASSERT_EQ(wide.exit_code, 0) << wide.err;
  const auto wide_manifest =
      nlohmann::json::parse(test::read_file(tmp_ / "wide" / "campaign.json"));
  EXPECT_EQ(wide_manifest["campaign_sha256"],
            "d5ceaa98e7dc3d05afda877abba43e35693c827de65880b44c62295fffb492ac");
  EXPECT_EQ(csv_records(tmp_ / "wide" / "results.csv").at(0).at("seed"), "17479650605290651281");
}

// Each row of a campaign over the three restorations is the simulator's run of its setting: the
// predicted RMSE it prints, its measured means, the lambda it applied and the level it fitted.
TEST_F(RestorationCampaignCli, EachRowIsTheSimulatorsRunOfItsSetting) {
  const fs::path dir = tmp_ / "c";
  const auto r = run_fssim(base_ + " --snr 60 --trials 2" + axis_ + " -o " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = csv_records(dir / "results.csv");
  ASSERT_EQ(rows.size(), 5u);  // inverse, tikhonov x 2 lambdas, wiener x 2 priors
  for (const auto& row : rows) {
    SCOPED_TRACE(restoration_options(row));
    ASSERT_EQ(row.at("status"), "ok") << row.at("message");
    std::string out;
    const nlohmann::json report =
        simulate("--snr 60 --trials 2 --seed " + row.at("seed") + restoration_options(row), &out);
    EXPECT_EQ(std::stod(row.at("predicted_rmse")), report["prediction"]["rmse"].get<double>());
    EXPECT_NEAR(std::stod(row.at("predicted_rmse")), printed(out, "Predicted RMSE: "), 5e-7);
    EXPECT_EQ(std::stod(row.at("rmse_mean")), report["trials"]["rmse_mean"].get<double>());
    EXPECT_EQ(std::stod(row.at("ssim_mean")), report["trials"]["ssim_mean"].get<double>());
    const nlohmann::json restoration = report.value("restoration", nlohmann::json::object());
    if (row.at("restoration") == "tikhonov") {
      EXPECT_EQ(std::stod(row.at("regularization_applied")),
                restoration["regularization"].get<double>());
    }
    if (row.at("prior").rfind("power-law", 0) == 0) {
      EXPECT_EQ(std::stod(row.at("prior_level")), restoration["prior_level"].get<double>());
    }
  }
  // Its results check against themselves, the new columns included.
  const auto check =
      run_fssim("campaign check " + quote(dir / "results.csv") + " " + quote(dir / "results.csv"));
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// A lambda or a prior that no setting would use is refused, in one line naming the option or
// the campaign file's key, before anything is written; sweep refuses as the simulator does.
TEST_F(RestorationCampaignCli, OptionsNoSettingUsesAreRefused) {
  const fs::path out = tmp_ / "out";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base_ + " --regularization 0.01", "--regularization"},
      {base_ + " --restoration inverse,wiener --regularization optimal", "--regularization"},
      {base_ + " --restoration tikhonov --prior oracle", "--prior"},
      {base_ + " --restoration wiener --prior power-law:2:180", "--prior"},
      {base_ + " --restoration deblur", "--restoration"},
      {"sweep -i " + quote(image_) + " --regularization 0.01", "--regularization"},
      {"sweep -i " + quote(image_) + " --restoration tikhonov --prior oracle", "--prior"}};
  for (const auto& [args, option] : cases) {
    const auto r = run_fssim(args + " -o " + quote(out));
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  const fs::path file = tmp_ / "c.json";
  test::write_file(file, "{\"input\": \"" + image_ +
                             "\", \"code\": \"raskar\", \"prior\": "
                             "\"oracle\"}");
  const auto r = run_fssim("campaign -f " + quote(file) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("\"prior\": applies to the wiener restoration only"), std::string::npos)
      << r.err;
}

std::string outputs(const fs::path& dir) {
  return test::read_file(dir / "results.csv") + test::read_file(dir / "results.jsonl") +
         test::read_file(dir / "campaign.json") + test::read_file(dir / "trials.csv");
}

// A journal cut as a kill leaves it, and shards merged, give the bytes of one run.
TEST_F(RestorationCampaignCli, TheRestorationAxisResumesAndMerges) {
  const std::string args = base_ + " --snr 40,80 --trials 2 --per-trial" + axis_;
  ASSERT_EQ(run_fssim(args + " -o " + quote(tmp_ / "whole")).exit_code, 0);
  const auto lines = test::lines_of(test::read_file(tmp_ / "whole" / "journal.jsonl"));
  ASSERT_EQ(lines.size(), 11u);
  fs::create_directories(tmp_ / "cut");
  std::string cut = lines[0] + "\n" + lines[1] + "\n" + lines[2] + "\n" + lines[3] + "\n";
  test::write_file(tmp_ / "cut" / "journal.jsonl", cut + lines[4].substr(0, 40));
  const auto resumed = run_fssim(args + " -o " + quote(tmp_ / "cut"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("(7 run now, 3 from the journal)"), std::string::npos) << resumed.out;
  EXPECT_EQ(outputs(tmp_ / "cut"), outputs(tmp_ / "whole"));
  std::string parts;
  for (int i = 1; i <= 3; ++i) {
    const fs::path part = tmp_ / ("part" + std::to_string(i));
    const auto r = run_fssim(args + " --shard " + std::to_string(i) + "/3 -o " + quote(part));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    parts += " " + quote(part);
  }
  const auto merged = run_fssim("campaign merge --figures -o " + quote(tmp_ / "merged") + parts);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(outputs(tmp_ / "merged"), outputs(tmp_ / "whole"));
  EXPECT_TRUE(fs::exists(tmp_ / "merged" / "figures" / "rmse_vs_snr__crop__numerical.svg"));
}

const char kSweepHeader[] =
    "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,snr_level100,"
    "invertible,status";

// sweep with a restoration: each row is the simulator's run with the sweep's seed; its CSV ends
// with the restoration's columns, and the inverse filter's CSV keeps its bytes.
TEST_F(RestorationCampaignCli, SweepWithARestorationIsTheSimulator) {
  const std::string sweep = "sweep --threads 1 -i " + quote(image_) + " -c " + quote(code_) +
                            " --snr 50:100:50 --trials 2";
  const auto plain = run_fssim(sweep + " -o -");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(test::lines_of(plain.out).at(0), kSweepHeader);
  const auto inverse = run_fssim(sweep + " --restoration inverse -o -");
  EXPECT_EQ(inverse.out, plain.out);
  for (const char* restoration : {"tikhonov", "wiener --prior oracle"}) {
    const fs::path csv = tmp_ / "sweep.csv";
    const auto r = run_fssim(sweep + " --restoration " + restoration + " -o " + quote(csv));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test::lines_of(test::read_file(csv)).at(0),
              std::string(kSweepHeader) +
                  ",restoration,regularization,prior,regularization_applied,prior_level,"
                  "noise_variance,ssim_mean,ssim_sd");
    for (const auto& row : csv_records(csv)) {
      SCOPED_TRACE(std::string(restoration) + ", snr " + row.at("snr"));
      const nlohmann::json report =
          simulate("--snr " + row.at("snr") + " --trials 2 --restoration " + restoration, nullptr);
      EXPECT_EQ(std::stod(row.at("predicted_rmse")), report["prediction"]["rmse"].get<double>());
      EXPECT_EQ(std::stod(row.at("rmse_mean")), report["trials"]["rmse_mean"].get<double>());
      EXPECT_EQ(std::stod(row.at("ssim_mean")), report["trials"]["ssim_mean"].get<double>());
      EXPECT_EQ(row.at("snr_level100"), "");  // the inverse filter's figure of merit
    }
  }
}

}  // namespace
}  // namespace fss
