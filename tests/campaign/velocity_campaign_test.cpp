// Velocity distributions in a campaign (docs/campaign.md, docs/method.md §13): the axis in place
// of the velocities, its canonical form, hash and seeds, its refusals, its rows against
// fss::Simulate, its files (results schema 4), resume, figures and the check against the
// predictions.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fss/campaign/check.h"
#include "fss/campaign/figures.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;

// A 120 x 24 crop of data/camera.png, written into `dir`.
std::string write_crop(const fs::path& dir) {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(120, 24, 1);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 300 + y, 180 + x);
  }
  const auto png = encode_png8(crop);
  const fs::path path = dir / "crop.png";
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

// A short code (L = 8), invertible over [0.5, 1.5], so that the crop fits its blur.
std::string write_short_code(const fs::path& dir) {
  const fs::path path = dir / "short.txt";
  test::write_file(path, "1 0 1 1 0 0 1 1\n");
  return path.string();
}

// A discrete distribution: velocities 0.75 and 1.25, weights 1 and 3.
std::string write_velocity_file(const fs::path& dir) {
  const fs::path path = dir / "velocities.txt";
  test::write_file(path, "# velocity weight\n0.75 1\n1.25 3\n");
  return path.string();
}

// One image, one code, two snr values, a uniform and a discrete distribution.
CampaignSpec distribution_spec(const test::TempDir& tmp) {
  CampaignSpec spec;
  spec.inputs = {write_crop(tmp.path())};
  spec.codes = {write_short_code(tmp.path())};
  spec.snr = "50,200";
  spec.trials = 3;
  spec.seed = 11;
  spec.velocity_distributions = {"uniform:0.5:1.5", write_velocity_file(tmp.path())};
  return spec;
}

std::string cell(const ResultRow& row, const char* column) {
  const int i = campaign_column_index(column);
  EXPECT_GE(i, 0) << column;
  return i >= 0 && static_cast<std::size_t>(i) < row.size() ? row[static_cast<std::size_t>(i)]
                                                            : "<no such column>";
}

TEST(VelocityCampaign, DistributionsAreAnAxisInPlaceOfTheVelocities) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(distribution_spec(tmp));
  ASSERT_EQ(c.velocity_distributions.size(), 2u);
  EXPECT_EQ(c.velocity_distributions[0].name, "uniform:0.5:1.5");
  EXPECT_EQ(c.velocity_distributions[1].distribution.kind, VelocityDistributionKind::kDiscrete);
  EXPECT_EQ(c.velocity_distributions[1].distribution.points.size(), 2u);
  EXPECT_EQ(c.setting_count(), 2 * 2);
  // The distribution varies as the velocity would: before the snr values.
  const std::vector<std::pair<int, int>> order = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
  for (int i = 0; i < 4; ++i) {
    const Setting s = setting_at(c, i);
    EXPECT_EQ(s.velocity_distribution, order[i].first) << i;
    EXPECT_EQ(s.snr, order[i].second) << i;
    const SimulationOptions o = setting_options(c, s);
    ASSERT_TRUE(o.velocity_distribution.has_value());
    EXPECT_EQ(o.velocity_distribution->text(),
              c.velocity_distributions[s.velocity_distribution].distribution.text());
    EXPECT_EQ(o.velocity_px_per_slot, 1.0);  // the default, unused
    // The description names the distribution by its digest, not a velocity.
    const auto description = nlohmann::json::parse(setting_description(c, s));
    EXPECT_FALSE(description.contains("velocity"));
    EXPECT_EQ(description.at("velocity_distribution_sha256"),
              c.velocity_distributions[s.velocity_distribution].sha256);
  }
  EXPECT_NE(setting_seed(c, setting_at(c, 0)), setting_seed(c, setting_at(c, 2)));
  // The canonical JSON holds the file's points: it rebuilds the campaign without the file.
  EXPECT_NE(c.canonical_json.find("\"velocity_distribution\""), std::string::npos);
  fs::remove(tmp / "velocities.txt");
  const ResolvedCampaign rebuilt = campaign_from_canonical_json(c.canonical_json);
  EXPECT_EQ(rebuilt.sha256, c.sha256);
  EXPECT_EQ(rebuilt.velocity_distributions[1].sha256, c.velocity_distributions[1].sha256);
  EXPECT_EQ(setting_seed(rebuilt, setting_at(rebuilt, 3)), setting_seed(c, setting_at(c, 3)));
}

// A campaign without distributions names none: its canonical JSON, hash and seeds are those it
// had before them. Two spellings of one distribution are one, with one hash.
TEST(VelocityCampaign, HashAndSpellings) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.velocity_distributions.clear();
  const ResolvedCampaign plain = resolve_campaign(spec);
  EXPECT_FALSE(plain.has_velocity_distributions());
  EXPECT_EQ(plain.canonical_json.find("velocity_distribution"), std::string::npos);
  EXPECT_EQ(setting_at(plain, 0).velocity_distribution, -1);
  EXPECT_NE(setting_description(plain, setting_at(plain, 0)).find("\"velocity\":1"),
            std::string::npos);
  spec.velocity_distributions = {"normal:1:0.1", "normal:1.0:0.10", "uniform:0.5:1.5"};
  const ResolvedCampaign twice = resolve_campaign(spec);
  ASSERT_EQ(twice.velocity_distributions.size(), 2u);
  EXPECT_EQ(twice.velocity_distributions[0].name, "normal:1:0.1");
  spec.velocity_distributions = {"normal:1:0.1", "uniform:0.5:1.5"};
  EXPECT_EQ(resolve_campaign(spec).sha256, twice.sha256);
  spec.velocity_distributions = {"uniform:0.5:1.5", "normal:1:0.1"};
  EXPECT_NE(resolve_campaign(spec).sha256, twice.sha256);  // another order, other rows
  // A file's distribution is its points: another file with the same points has other rows'
  // names, but the same seeds.
  CampaignSpec a = distribution_spec(tmp);
  a.velocity_distributions = {write_velocity_file(tmp.path())};
  test::write_file(tmp / "same.txt", "1.25 6\n0.75 2\n");
  CampaignSpec b = a;
  b.velocity_distributions = {(tmp / "same.txt").string()};
  const ResolvedCampaign ca = resolve_campaign(a), cb = resolve_campaign(b);
  EXPECT_EQ(ca.velocity_distributions[0].sha256, cb.velocity_distributions[0].sha256);
  EXPECT_EQ(setting_seed(ca, setting_at(ca, 0)), setting_seed(cb, setting_at(cb, 0)));
}

TEST(VelocityCampaign, RefusesWhatCannotRunOrWouldBeIgnored) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  const std::string key = "--velocity-distribution / \"velocity_distribution\"";
  spec.velocity = "0.5,1";
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"--velocity / \"velocity\" = 0.5,1", key, "not both"}));
  spec = distribution_spec(tmp);
  spec.velocity_distributions = {"uniform:1.5:0.5"};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {key, "uniform:1.5:0.5"}));
  spec.velocity_distributions = {"gamma:1:2"};
  EXPECT_TRUE(
      test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage, {key, "gamma:1:2"}));
  spec.velocity_distributions = {""};
  EXPECT_TRUE(
      test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage, {key, "empty"}));
  spec.velocity_distributions = {(tmp / "missing.txt").string()};
  EXPECT_TRUE(
      test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage, {key, "missing.txt"}));
  test::write_file(tmp / "bad.txt", "1 1\n2 x\n");
  spec.velocity_distributions = {(tmp / "bad.txt").string()};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kRuntime,
                                 {key, "bad.txt", "line 2"}));
  // The restorations a distribution allows are the library's: a Wiener restoration and
  // Tikhonov's optimal lambda are refused before any run, naming the distribution.
  spec = distribution_spec(tmp);
  spec.restorations = {"inverse", "wiener"};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {key, "uniform:0.5:1.5", "wiener"}));
  spec.restorations = {"tikhonov"};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {key, "tikhonov (lambda optimal)"}));
  spec.regularization = {"0.01"};
  EXPECT_EQ(resolve_campaign(spec).restorations.size(), 1u);
}

// The campaign file: its key, refused with the velocity key and, for a bad item, naming the file,
// the key and the item.
TEST(VelocityCampaign, CampaignFileKey) {
  test::TempDir tmp;
  const CampaignSpec spec = parse_campaign_file(
      R"({"input": "a.png", "code": "raskar", "velocity_distribution": ["uniform:0.5:1.5",
          "normal:1:0.2"]})",
      "c.json");
  EXPECT_EQ(spec.velocity_distributions,
            (std::vector<std::string>{"uniform:0.5:1.5", "normal:1:0.2"}));
  EXPECT_EQ(parse_campaign_file(R"({"velocity_distribution": "uniform:0.5:1.5"})", "c.json")
                .velocity_distributions.size(),
            1u);
  EXPECT_TRUE(test::throws_error(
      [&] {
        parse_campaign_file(R"({"velocity": 1, "velocity_distribution": "uniform:0:1"})", "c.json");
      },
      ErrorKind::kUsage, {"campaign file 'c.json'", "'velocity' and 'velocity_distribution'"}));
  EXPECT_TRUE(test::throws_error(
      [&] { parse_campaign_file(R"({"velocity_distribution": ["normal:1"]})", "c.json"); },
      ErrorKind::kUsage, {"campaign file 'c.json'", "\"velocity_distribution\"", "normal:1"}));
  EXPECT_TRUE(test::throws_error(
      [&] { parse_campaign_file(R"({"velocity_distribution": []})", "c.json"); }, ErrorKind::kUsage,
      {"campaign file 'c.json'", "'velocity_distribution' is an empty list"}));
  EXPECT_TRUE(test::throws_error(
      [&] { parse_campaign_file(R"({"velocity_distribution": [1.5]})", "c.json"); },
      ErrorKind::kUsage, {"campaign file 'c.json'", "'velocity_distribution' takes strings"}));
  test::write_file(tmp / "bad.txt", "0.5 -1\n");
  const std::string bad = (tmp / "bad.txt").string();
  EXPECT_TRUE(test::throws_error(
      [&] { parse_campaign_file(R"({"velocity_distribution": ")" + bad + "\"}", "c.json"); },
      ErrorKind::kRuntime, {"campaign file 'c.json'", "\"velocity_distribution\"", "bad.txt"}));
}

// Each row is fss::Simulate's run of its setting: the distribution, the trials' MSE mean and sd,
// E[MSE]; no velocity; each trial row its velocity.
TEST(VelocityCampaign, RowsAreTheSimulationsOfTheirSetting) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.restore_velocity = "1.1";
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  const Image image = read_png(c.images[0].path);
  SimulationPlanCache plans;
  for (long long i = 0; i < c.setting_count(); ++i) {
    const Setting s = setting_at(c, i);
    std::vector<ResultRow> trials;
    const ResultRow row = run_setting(c, s, image, {1, 0, "v"}, &plans, &trials);
    ASSERT_EQ(row.size(), campaign_columns(true).size());
    ASSERT_EQ(cell(row, "status"), kStatusOk) << cell(row, "message");
    const SimulationReport r = Simulate(setting_options(c, s), image, c.codes[0].code);
    EXPECT_EQ(cell(row, "velocity"), "");
    EXPECT_EQ(cell(row, "restore_velocity"), "1.1");
    EXPECT_EQ(cell(row, "velocity_distribution"),
              c.velocity_distributions[s.velocity_distribution].name);
    ASSERT_TRUE(r.trials.mse_mean && r.trials.mse_sd && r.prediction.mse);
    EXPECT_EQ(std::stod(cell(row, "mse_mean")), *r.trials.mse_mean) << i;
    EXPECT_EQ(std::stod(cell(row, "mse_sd")), *r.trials.mse_sd) << i;
    EXPECT_EQ(std::stod(cell(row, "predicted_mse")), *r.prediction.mse) << i;
    EXPECT_EQ(std::stod(cell(row, "predicted_rmse")), r.prediction.rmse) << i;
    EXPECT_EQ(std::stod(cell(row, "rmse_mean")), r.trials.rmse_mean) << i;
    ASSERT_EQ(trials.size(), 3u);
    ASSERT_EQ(r.trial_velocities.size(), 3u);
    const auto& columns = trial_columns(true);
    for (std::size_t t = 0; t < trials.size(); ++t) {
      ASSERT_EQ(trials[t].size(), columns.size());
      EXPECT_EQ(trials[t][columns.size() - 2], cell(row, "velocity_distribution"));
      EXPECT_EQ(std::stod(trials[t].back()), r.trial_velocities[t]) << i << " " << t;
    }
  }
  // The discrete distribution's trials observe its velocities only.
  const SimulationReport discrete =
      Simulate(setting_options(c, setting_at(c, 2)), image, c.codes[0].code);
  for (const double v : discrete.trial_velocities) EXPECT_TRUE(v == 0.75 || v == 1.25) << v;
}

// The files: schema 4 with the distribution's columns after schema 3's; a killed run resumed and
// two shards merged give the same bytes.
TEST(VelocityCampaign, FilesResumeAndMerge) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  const CampaignRunSummary full = RunCampaign(c, (tmp / "full").string(), {});
  const auto rows = parse_csv(test::read_file(tmp / "full" / kCampaignResultsCsv), "r.csv");
  ASSERT_EQ(rows.size(), 5u);
  ASSERT_EQ(rows[0].size(), campaign_columns(true).size());
  EXPECT_EQ(
      std::vector<std::string>(rows[0].end() - 4, rows[0].end()),
      (std::vector<std::string>{"velocity_distribution", "mse_mean", "mse_sd", "predicted_mse"}));
  const auto trials = parse_csv(test::read_file(tmp / "full" / kCampaignTrialsCsv), "t.csv");
  EXPECT_EQ(trials[0].back(), "trial_velocity");
  EXPECT_EQ(trials.size(), 1u + 4u * 3u);
  const auto manifest = nlohmann::json::parse(test::read_file(tmp / "full" / kCampaignManifest));
  EXPECT_EQ(manifest["schema_version"], kCampaignDistributionSchemaVersion);
  const auto jsonl = test::lines_of(test::read_file(tmp / "full" / kCampaignResultsJsonl));
  EXPECT_NE(jsonl[0].find("\"velocity\":null,"), std::string::npos) << jsonl[0];
  EXPECT_NE(jsonl[0].find("\"velocity_distribution\":\"uniform:0.5:1.5\""), std::string::npos);
  // Resume after a kill that left two settings.
  const std::vector<std::string> lines =
      test::lines_of(test::read_file(tmp / "full" / kCampaignJournal));
  fs::create_directories(tmp / "cut");
  test::write_file(tmp / "cut" / kCampaignJournal,
                   lines[0] + "\n" + lines[1] + "\n" + lines[2] + "\n" + lines[3].substr(0, 20));
  const CampaignRunSummary resumed = RunCampaign(c, (tmp / "cut").string(), {});
  EXPECT_EQ(resumed.resumed, 2);
  for (const char* name : {kCampaignJournal, kCampaignResultsCsv, kCampaignResultsJsonl,
                           kCampaignTrialsCsv, kCampaignTrialsJsonl, kCampaignManifest}) {
    EXPECT_EQ(test::read_file(tmp / "cut" / name), test::read_file(tmp / "full" / name)) << name;
  }
  // Two shards merged.
  for (int i = 1; i <= 2; ++i) {
    CampaignRunOptions options;
    options.shard = {i, 2};
    RunCampaign(c, (tmp / ("part" + std::to_string(i))).string(), options);
  }
  ResolvedCampaign merged_campaign;
  MergeCampaignParts({(tmp / "part1").string(), (tmp / "part2").string()},
                     (tmp / "merged").string(), &merged_campaign);
  EXPECT_EQ(merged_campaign.sha256, c.sha256);
  for (const char* name : {kCampaignJournal, kCampaignResultsCsv, kCampaignTrialsCsv}) {
    EXPECT_EQ(test::read_file(tmp / "merged" / name), test::read_file(tmp / "full" / name)) << name;
  }
  // A journal row of the other schema (no distribution columns) is not this campaign's.
  nlohmann::json row = nlohmann::json::parse(lines[1]);
  auto cells = row["row"].get<ResultRow>();
  cells.resize(campaign_columns().size());
  row["row"] = cells;
  row.erase("trials");
  fs::create_directories(tmp / "narrow");
  test::write_file(tmp / "narrow" / kCampaignJournal, lines[0] + "\n" + row.dump() + "\n");
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "narrow").string(), {}); },
                                 ErrorKind::kRuntime, {"velocity_distribution differs"}));
  EXPECT_EQ(full.rows.size(), 4u);
}

// A support that reaches a velocity where the code is not invertible: the inverse filter's row
// is not-invertible with an infinite E[MSE]; at a restore velocity where it is invertible, or
// under Tikhonov, the row runs.
TEST(VelocityCampaign, ASupportBeyondInvertibilityIsNotInvertible) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.velocity_distributions = {"uniform:1:2", "uniform:0.5:1.5"};
  spec.snr = "100";
  spec.rmse_margin_columns = 10;
  spec.restorations = {"inverse", "tikhonov"};
  spec.regularization = {"0.01"};
  const ResolvedCampaign c = resolve_campaign(spec);
  const Image image = read_png(c.images[0].path);
  const std::vector<std::vector<std::string>> expected = {{"false", "not-invertible", "inf"},
                                                          {"false", "ok", ""},
                                                          {"true", "ok", ""},
                                                          {"true", "ok", ""}};
  ASSERT_EQ(c.setting_count(), 4);
  for (long long i = 0; i < 4; ++i) {
    const ResultRow row = run_setting(c, setting_at(c, i), image, {});
    EXPECT_EQ(cell(row, "invertible"), expected[i][0]) << i;
    EXPECT_EQ(cell(row, "status"), expected[i][1]) << i << cell(row, "message");
    if (!expected[i][2].empty()) EXPECT_EQ(cell(row, "predicted_mse"), expected[i][2]) << i;
    if (expected[i][2].empty()) EXPECT_TRUE(std::isfinite(std::stod(cell(row, "predicted_mse"))));
  }
  spec.velocity_distributions = {"uniform:1:2"};
  spec.restorations.clear();
  spec.regularization.clear();
  spec.restore_velocity = "1";
  const ResolvedCampaign restored = resolve_campaign(spec);
  const ResultRow row = run_setting(restored, setting_at(restored, 0), image, {});
  EXPECT_EQ(cell(row, "invertible"), "true");
  EXPECT_EQ(cell(row, "status"), "ok");
}

// A velocity file is an input: a run never writes over it.
TEST(VelocityCampaign, NeverWritesOverAVelocityFile) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  fs::create_directories(tmp / "out");
  test::write_file(tmp / "out" / kCampaignResultsCsv, "1 1\n");
  spec.velocity_distributions = {(tmp / "out" / kCampaignResultsCsv).string()};
  EXPECT_TRUE(
      test::throws_error([&] { RunCampaign(resolve_campaign(spec), (tmp / "out").string(), {}); },
                         ErrorKind::kUsage, {"would replace the input"}));
  EXPECT_EQ(test::read_file(tmp / "out" / kCampaignResultsCsv), "1 1\n");
}

// A campaign without distributions keeps schema 3: its columns, its manifest's version.
TEST(VelocityCampaign, ACampaignWithoutDistributionsKeepsSchema3) {
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.velocity_distributions.clear();
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  RunCampaign(c, (tmp / "out").string(), {});
  const auto rows = parse_csv(test::read_file(tmp / "out" / kCampaignResultsCsv), "r.csv");
  EXPECT_EQ(rows[0].size(), campaign_columns().size());
  EXPECT_EQ(rows[0].back(), "fssim_version");
  const auto trials = parse_csv(test::read_file(tmp / "out" / kCampaignTrialsCsv), "t.csv");
  EXPECT_EQ(trials[0].back(), "ssim");
  const auto manifest = nlohmann::json::parse(test::read_file(tmp / "out" / kCampaignManifest));
  EXPECT_EQ(manifest["schema_version"], kCampaignSchemaVersion);
  EXPECT_EQ(rows[1][campaign_column_index("velocity")], "1");
}

// The figures plot sqrt(mean MSE), labelled so, one figure per distribution.
TEST(VelocityCampaign, FiguresPlotTheRootOfTheMeanMse) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(distribution_spec(tmp));
  const CampaignRunSummary run = RunCampaign(c, (tmp / "out").string(), {});
  const std::vector<CampaignFigure> figures = campaign_figures(c, run.rows);
  ASSERT_EQ(figures.size(), 2u);  // snr swept, once per distribution
  EXPECT_NE(figures[0].svg.find("sqrt(mean MSE) vs snr"), std::string::npos);
  EXPECT_NE(figures[0].svg.find("v ~ uniform:0.5:1.5"), std::string::npos);
  EXPECT_NE(figures[1].svg.find("v ~ " + c.velocity_distributions[1].name), std::string::npos);
  EXPECT_NE(figures[0].svg.find(">sqrt(mean MSE) (gray levels)<"), std::string::npos);
  EXPECT_NE(figures[0].svg.find(">measured: sqrt(mean MSE) ± 1.96 SE<"), std::string::npos);
  EXPECT_EQ(figures[0].svg.find("RMSE vs"), std::string::npos);
}

const char kPredictedResults[] =
    "image,code,velocity,snr,trials,rmse_mean,rmse_sd,predicted_rmse,status,"
    "velocity_distribution,mse_mean,mse_sd,predicted_mse\n"
    "a.png,raskar,,100,400,2.0,0.5,2.1,ok,uniform:0.5:1.5,4.2,2.0,4.1\n"
    "a.png,raskar,,200,400,2.0,0.5,2.1,ok,uniform:0.5:1.5,4.5,2.0,4.1\n"
    "a.png,raskar,1,100,100,2.35,0.02,2.349,ok,,,,\n"
    "a.png,raskar,1,200,1,2.35,0,2.349,ok,,,,\n"
    "a.png,mip,,100,400,,,inf,not-invertible,uniform:0.5:1.5,,,inf\n";

// The check against the predictions: under a distribution z = (mse_mean - predicted_mse) /
// (mse_sd / sqrt(trials)); otherwise the RMSE; rows that cannot be compared are left out.
TEST(VelocityCampaign, CheckComparesTheMeanMseWithItsPrediction) {
  CheckOptions options;
  options.k_standard_errors = 3;
  options.rel_tolerance = 1e-9;
  const CheckReport report = CheckCampaignPredictions(kPredictedResults, "r.csv", options);
  // SE 2 / 20 = 0.1: 4.2 vs 4.1 is z = 1, 4.5 vs 4.1 z = 4; the RMSE row: SE 0.002, z = 0.5.
  ASSERT_EQ(report.cases.size(), 3u);
  EXPECT_EQ(report.cases[0].column, "mse_mean");
  EXPECT_TRUE(report.cases[0].passed) << report.cases[0].message;
  EXPECT_FALSE(report.cases[1].passed);
  EXPECT_NE(report.cases[1].message.find("line 3: code=raskar velocity= snr=200"),
            std::string::npos)
      << report.cases[1].message;
  EXPECT_NE(report.cases[1].message.find("mse_mean 4.5, predicted_mse 4.1"), std::string::npos);
  EXPECT_NE(report.cases[1].message.find("z = 4"), std::string::npos) << report.cases[1].message;
  EXPECT_EQ(report.cases[2].column, "rmse_mean");
  EXPECT_TRUE(report.cases[2].passed) << report.cases[2].message;
  options.k_standard_errors = 5;
  EXPECT_EQ(CheckCampaignPredictions(kPredictedResults, "r.csv", options).failures(), 0);
  options.columns = {"mse_mean"};
  EXPECT_TRUE(
      test::throws_error([&] { CheckCampaignPredictions(kPredictedResults, "r.csv", options); },
                         ErrorKind::kUsage, {"--columns"}));
  options.columns.clear();
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignPredictions("code,rmse_mean\nraskar,1\n", "r.csv", options); },
      ErrorKind::kUsage, {"'r.csv' has no column 'status'"}));
  const std::string missing =
      "trials,rmse_mean,rmse_sd,predicted_rmse,status,velocity_distribution,mse_mean,mse_sd,"
      "predicted_mse\n300,2,1,2,ok,normal:1:0.1,,1,4\n";
  const CheckReport gap = CheckCampaignPredictions(missing, "r.csv", options);
  ASSERT_EQ(gap.cases.size(), 1u);
  EXPECT_FALSE(gap.cases[0].passed);
  EXPECT_NE(gap.cases[0].message.find("mse_mean missing, predicted_mse 4"), std::string::npos)
      << gap.cases[0].message;
  const std::string nothing =
      "code,trials,rmse_mean,rmse_sd,predicted_rmse,status\nraskar,1,2,0,2,ok\n";
  EXPECT_TRUE(test::throws_error([&] { CheckCampaignPredictions(nothing, "r.csv", options); },
                                 ErrorKind::kUsage, {"no row to compare"}));
  // The results' distribution columns select rows of an EXPECTED file; mse_mean has a standard
  // error from mse_sd, as rmse_mean has from rmse_sd.
  const std::string expected =
      "code,snr,velocity_distribution,trials,mse_mean,mse_sd\n"
      "raskar,200,uniform:0.5:1.5,400,4.3,2.0\n";
  options.k_standard_errors = 3;
  const CheckReport against =
      CheckCampaignResults(kPredictedResults, "r.csv", expected, "e.csv", options);
  ASSERT_EQ(against.cases.size(), 1u);
  EXPECT_TRUE(against.cases[0].passed) << against.cases[0].message;  // 0.2 / 0.141 = 1.4 SE
}

// A statistical check, over the settings of a campaign (several snr values and distributions,
// each its own seeds): the mean of the trials' MSE agrees with E[MSE] within 3 standard errors.
TEST(VelocityCampaign, TheTrialsAgreeWithThePredictionInEverySetting) {
  if (test::kAddressSanitizer) {
    GTEST_SKIP() << "Monte Carlo over 6 x 300 trials: run in the Release suite";
  }
  test::TempDir tmp;
  CampaignSpec spec = distribution_spec(tmp);
  spec.snr = "30,100,300";
  spec.trials = 300;
  spec.velocity_distributions.push_back("normal:1:0.15");
  spec.velocity_distributions.erase(spec.velocity_distributions.begin() + 1);
  const ResolvedCampaign c = resolve_campaign(spec);
  RunCampaign(c, (tmp / "out").string(), {});
  CheckOptions options;
  options.k_standard_errors = 3;
  const CheckReport report = CheckCampaignPredictions(
      test::read_file(tmp / "out" / kCampaignResultsCsv), "results.csv", options);
  ASSERT_EQ(report.cases.size(), 6u);
  for (const CheckCase& k : report.cases) {
    EXPECT_EQ(k.column, "mse_mean");
    EXPECT_TRUE(k.passed) << k.message;
  }
}

}  // namespace
}  // namespace fss
