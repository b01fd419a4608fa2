// The restorations of a campaign (docs/campaign.md): the axis of restoration variants, its
// canonical form and seeds, its rows against fss::Simulate, its refusals, its resume (also from a
// journal an earlier fssim wrote), its figures and the regression check of its new columns.
#include <gtest/gtest.h>

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
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 240 + y, 200 + x);
  }
  const auto png = encode_png8(crop);
  const fs::path path = dir / "crop.png";
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

// A short code (L = 8), invertible at velocity 1, so that the crop fits its blur.
std::string write_short_code(const fs::path& dir) {
  const fs::path path = dir / "short.txt";
  test::write_file(path, "1 0 1 1 0 0 1 1\n");
  return path.string();
}

// One image, one code, two snr values, the three restorations: inverse, tikhonov at 0.01 and
// optimal, wiener with the power-law and the oracle prior.
CampaignSpec restoration_spec(const test::TempDir& tmp) {
  CampaignSpec spec;
  spec.inputs = {write_crop(tmp.path())};
  spec.codes = {write_short_code(tmp.path())};
  spec.snr = "50,200";
  spec.trials = 2;
  spec.seed = 5;
  spec.restorations = {"inverse,tikhonov", "wiener"};
  spec.regularization = {"0.01", "optimal"};
  spec.priors = {"power-law:2,oracle"};
  return spec;
}

std::string cell(const ResultRow& row, const char* column) {
  return row[static_cast<std::size_t>(campaign_column_index(column))];
}

TEST(RestorationCampaign, VariantsAreAnAxisWithoutMeaninglessCombinations) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(restoration_spec(tmp));
  // inverse once, tikhonov at each lambda, wiener with each prior: 5, not 3 x 2 x 2.
  ASSERT_EQ(c.restorations.size(), 5u);
  EXPECT_EQ(describe(c.restorations[0]), "inverse");
  EXPECT_EQ(describe(c.restorations[1]), "tikhonov (lambda 0.01)");
  EXPECT_EQ(describe(c.restorations[2]), "tikhonov (lambda optimal)");
  EXPECT_EQ(describe(c.restorations[3]), "wiener (power-law prior, gamma 2)");
  EXPECT_EQ(describe(c.restorations[4]), "wiener (oracle prior)");
  EXPECT_EQ(c.setting_count(), 2 * 5);
  // The restoration varies fastest; the restorations of one observation share its seed.
  for (int r = 0; r < 5; ++r) {
    const Setting s = setting_at(c, r);
    EXPECT_EQ(s.restoration, r);
    EXPECT_EQ(s.snr, 0);
    EXPECT_EQ(setting_seed(c, s), setting_seed(c, setting_at(c, 0)));
    EXPECT_EQ(setting_options(c, s).restoration.method, c.restorations[r].method);
  }
  EXPECT_NE(setting_seed(c, setting_at(c, 5)), setting_seed(c, setting_at(c, 0)));
  EXPECT_NE(c.canonical_json.find("\"restoration\""), std::string::npos);
  EXPECT_EQ(campaign_from_canonical_json(c.canonical_json).sha256, c.sha256);
  // A variant named twice, in two spellings, runs once.
  CampaignSpec spec = restoration_spec(tmp);
  spec.restorations = {"wiener,inverse", "inverse"};
  spec.regularization.clear();
  spec.priors = {"power-law", "power-law:2", "oracle", "oracle"};
  const ResolvedCampaign twice = resolve_campaign(spec);
  ASSERT_EQ(twice.restorations.size(), 3u);
  EXPECT_EQ(twice.restorations[2].method, RestorationMethod::kInverse);
  // The inverse filter alone, spelled out, is a campaign without restorations.
  spec.restorations = {"inverse"};
  spec.priors.clear();
  const ResolvedCampaign inverse = resolve_campaign(spec);
  EXPECT_FALSE(inverse.has_restorations());
  EXPECT_EQ(inverse.canonical_json.find("restoration"), std::string::npos);
  spec.restorations.clear();
  EXPECT_EQ(resolve_campaign(spec).sha256, inverse.sha256);
}

// Each row is fss::Simulate's run of its setting: the restoration asked, the lambda applied, the
// fitted prior level, the SSIM, the exact prediction.
TEST(RestorationCampaign, RowsAreTheSimulationsOfTheirRestoration) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(restoration_spec(tmp));
  const Image image = read_png(c.images[0].path);
  SimulationPlanCache plans;
  for (long long i = 0; i < 5; ++i) {
    const Setting s = setting_at(c, i);
    std::vector<ResultRow> trials;
    const ResultRow row = run_setting(c, s, image, {1, 0, "v"}, &plans, &trials);
    const SimulationReport r = Simulate(setting_options(c, s), image, c.codes[0].code);
    ASSERT_EQ(cell(row, "status"), "ok") << cell(row, "message");
    EXPECT_EQ(cell(row, "restoration"), to_string(c.restorations[i].method));
    EXPECT_EQ(std::stod(cell(row, "predicted_rmse")), r.prediction.rmse) << i;
    EXPECT_EQ(std::stod(cell(row, "rmse_mean")), r.trials.rmse_mean) << i;
    ASSERT_TRUE(r.trials.ssim_mean.has_value());
    EXPECT_EQ(std::stod(cell(row, "ssim_mean")), *r.trials.ssim_mean) << i;
    EXPECT_EQ(std::stod(cell(row, "ssim_sd")), *r.trials.ssim_sd) << i;
    EXPECT_EQ(std::stod(trials.at(1).back()), *r.trial_metrics.at(1).ssim) << i;
    EXPECT_EQ(cell(row, "regularization_applied").empty(), !r.restoration.regularization);
    EXPECT_EQ(cell(row, "prior_level").empty(), !r.restoration.prior_level);
    EXPECT_EQ(cell(row, "snr_level100").empty(), i != 0);  // the inverse filter's figure
  }
  const ResultRow fixed = run_setting(c, setting_at(c, 1), image, {});
  EXPECT_EQ(cell(fixed, "regularization"), "0.01");
  EXPECT_EQ(cell(fixed, "regularization_applied"), "0.01");
  EXPECT_EQ(cell(fixed, "prior"), "");
  const ResultRow optimal = run_setting(c, setting_at(c, 2), image, {});
  EXPECT_EQ(cell(optimal, "regularization"), "optimal");
  EXPECT_GE(std::stod(cell(optimal, "regularization_applied")), kMinRegularization);
  const ResultRow power_law = run_setting(c, setting_at(c, 3), image, {});
  EXPECT_EQ(cell(power_law, "prior"), "power-law:2");
  EXPECT_EQ(cell(power_law, "regularization"), "");
  EXPECT_GT(std::stod(cell(power_law, "prior_level")), 0.0);
  EXPECT_GT(std::stod(cell(power_law, "noise_variance")), 0.0);
  const ResultRow oracle = run_setting(c, setting_at(c, 4), image, {});
  EXPECT_EQ(cell(oracle, "prior"), "oracle");
  EXPECT_EQ(cell(oracle, "prior_level"), "");
}

// Tikhonov and Wiener restore a code whose inverse filter does not exist: their rows are ok.
TEST(RestorationCampaign, ACodeThatIsNotInvertibleIsRestoredByTikhonovAndWiener) {
  test::TempDir tmp;
  CampaignSpec spec = restoration_spec(tmp);
  test::write_file(tmp / "box.txt", "1 1 1 1\n");
  spec.codes = {(tmp / "box.txt").string()};
  spec.snr = "100";
  spec.trials = 1;
  const ResolvedCampaign c = resolve_campaign(spec);
  const Image image = read_png(c.images[0].path);
  for (long long i = 0; i < c.setting_count(); ++i) {
    const ResultRow row = run_setting(c, setting_at(c, i), image, {});
    EXPECT_EQ(cell(row, "invertible"), "false");
    EXPECT_EQ(cell(row, "status"), i == 0 ? "not-invertible" : "ok") << i;
    EXPECT_EQ(cell(row, "predicted_rmse") == "inf", i == 0) << i;
  }
}

// A lambda or a prior without its method would be accepted and ignored: refused, naming the
// option and the key in one line; so are values out of range and unknown names.
TEST(RestorationCampaign, MeaninglessOrMalformedRestorationsAreRefused) {
  test::TempDir tmp;
  const auto refused = [&](CampaignSpec spec, std::initializer_list<std::string_view> parts) {
    const auto error = test::error_of([&] { resolve_campaign(spec); });
    if (!error) return ::testing::AssertionFailure() << "accepted";
    if (std::string(error->what()).find('\n') != std::string::npos) {
      return ::testing::AssertionFailure() << "not one line: " << error->what();
    }
    return test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage, parts);
  };
  CampaignSpec spec = restoration_spec(tmp);
  spec.restorations = {"inverse,wiener"};
  EXPECT_TRUE(refused(spec, {"--regularization / \"regularization\"", "tikhonov"}));
  spec.restorations = {"tikhonov"};
  EXPECT_TRUE(refused(spec, {"--prior / \"prior\"", "wiener"}));
  spec.restorations.clear();
  spec.priors.clear();
  EXPECT_TRUE(refused(spec, {"--regularization / \"regularization\"", "has no tikhonov"}));
  spec = restoration_spec(tmp);
  spec.restorations = {"inverse,lucy"};
  EXPECT_TRUE(refused(spec, {"--restoration / \"restoration\" item 'lucy'"}));
  spec = restoration_spec(tmp);
  spec.regularization = {"1e-3:1e3:x10"};
  EXPECT_TRUE(refused(spec, {"--regularization / \"regularization\" = 1000", "[1e-08, 100]"}));
  spec.regularization = {"best"};
  EXPECT_TRUE(refused(spec, {"item 'best'", "optimal"}));
  spec = restoration_spec(tmp);
  spec.priors = {"power-law:2:180"};
  EXPECT_TRUE(refused(spec, {"--prior / \"prior\" item 'power-law:2:180'", "level"}));
  spec.priors = {"power-law:9"};
  EXPECT_TRUE(refused(spec, {"--prior / \"prior\"", "GAMMA"}));
  // The campaign file's keys, refused the same way.
  const CampaignSpec file =
      parse_campaign_file(R"({"input": "x.png", "code": "raskar", "prior": ["oracle"]})", "c.json");
  EXPECT_EQ(file.priors, std::vector<std::string>{"oracle"});
  EXPECT_TRUE(
      test::throws_error([&] { parse_campaign_file(R"({"regularization": []})", "c.json"); },
                         ErrorKind::kUsage, {"'regularization' is an empty list"}));
  EXPECT_TRUE(test::throws_error([&] { parse_campaign_file(R"({"restoration": [1]})", "c.json"); },
                                 ErrorKind::kUsage, {"'restoration' takes strings"}));
}

std::string files_of(const fs::path& dir) {
  return test::read_file(dir / kCampaignResultsCsv) + test::read_file(dir / kCampaignResultsJsonl) +
         test::read_file(dir / kCampaignManifest) + test::read_file(dir / kCampaignTrialsCsv);
}

// A journal cut as a kill leaves it resumes the restoration axis to the bytes of one run.
TEST(RestorationCampaign, ResumeGivesTheBytesOfOneRun) {
  test::TempDir tmp;
  CampaignSpec spec = restoration_spec(tmp);
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  RunCampaign(c, (tmp / "full").string(), {});
  const std::vector<std::string> lines =
      test::lines_of(test::read_file(tmp / "full" / kCampaignJournal));
  fs::create_directories(tmp / "cut");
  std::string cut;
  for (int i = 0; i < 5; ++i) cut += lines[static_cast<std::size_t>(i)] + "\n";
  cut += lines[5].substr(0, lines[5].size() / 3);
  test::write_file(tmp / "cut" / kCampaignJournal, cut);
  const CampaignRunSummary resumed = RunCampaign(c, (tmp / "cut").string(), {});
  EXPECT_EQ(resumed.resumed, 4);
  EXPECT_EQ(resumed.ran, c.setting_count() - 4);
  EXPECT_EQ(files_of(tmp / "cut"), files_of(tmp / "full"));
}

// `row` (of `columns`) without the columns results schema 3 added: as an earlier fssim journalled
// it.
nlohmann::json schema2_row(const ResultRow& row, const std::vector<ResultColumn>& columns) {
  static const std::vector<std::string> added = {
      "restoration", "regularization", "prior", "ssim_mean", "ssim_sd", "regularization_applied",
      "prior_level", "noise_variance", "ssim"};
  nlohmann::json old = nlohmann::json::array();
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (std::find(added.begin(), added.end(), columns[i].name) == added.end()) {
      old.push_back(row[i]);
    }
  }
  return old;
}

// A journal an earlier fssim wrote (results schema 2: no restoration, no SSIM) still resumes: its
// rows keep their values in the present columns, with the inverse filter and no SSIM.
TEST(RestorationCampaign, AJournalOfAnEarlierFssimResumes) {
  test::TempDir tmp;
  CampaignSpec spec = restoration_spec(tmp);
  spec.restorations.clear();
  spec.regularization.clear();
  spec.priors.clear();
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  ASSERT_EQ(c.setting_count(), 2);
  const CampaignRunSummary full = RunCampaign(c, (tmp / "full").string(), {});
  const std::vector<std::string> lines =
      test::lines_of(test::read_file(tmp / "full" / kCampaignJournal));
  nlohmann::json first = nlohmann::json::parse(lines[1]);
  first["row"] = schema2_row(first["row"].get<ResultRow>(), campaign_columns());
  for (auto& trial : first["trials"]) trial = schema2_row(trial.get<ResultRow>(), trial_columns());
  fs::create_directories(tmp / "old");
  test::write_file(tmp / "old" / kCampaignJournal, lines[0] + "\n" + first.dump() + "\n");
  const CampaignRunSummary resumed = RunCampaign(c, (tmp / "old").string(), {});
  EXPECT_EQ(resumed.resumed, 1);
  EXPECT_EQ(resumed.ran, 1);
  ResultRow expected = full.rows[0];
  expected[campaign_column_index("ssim_mean")].clear();
  expected[campaign_column_index("ssim_sd")].clear();
  EXPECT_EQ(resumed.rows[0], expected);
  EXPECT_EQ(cell(resumed.rows[0], "restoration"), "inverse");
  EXPECT_EQ(resumed.rows[1], full.rows[1]);
  const auto trials = parse_csv(test::read_file(tmp / "old" / kCampaignTrialsCsv), "trials.csv");
  ASSERT_EQ(trials.size(), 1u + 2u * 2u);
  EXPECT_EQ(trials[1].back(), "");  // the earlier fssim's trial: no SSIM
  EXPECT_NE(trials[3].back(), "");  // this one's
}

TEST(RestorationCampaign, FiguresHaveACurvePerRestoration) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(restoration_spec(tmp));
  const CampaignRunSummary run = RunCampaign(c, (tmp / "out").string(), {});
  const std::vector<CampaignFigure> figures = campaign_figures(c, run.rows);
  ASSERT_EQ(figures.size(), 1u);  // snr is the one swept quantity
  // The curves are named by the code (its file's name) and the restoration.
  for (const char* name :
       {"short.txt: inverse", "short.txt: tikhonov (lambda 0.01)",
        "short.txt: tikhonov (lambda optimal)", "short.txt: wiener (power-law prior, gamma 2)",
        "short.txt: wiener (oracle prior)"}) {
    EXPECT_NE(figures[0].svg.find(std::string(">") + name + "<"), std::string::npos) << name;
  }
  // One restoration: named in the title, not on the curves.
  CampaignSpec spec = restoration_spec(tmp);
  spec.restorations = {"wiener"};
  spec.regularization.clear();
  spec.priors = {"oracle"};
  const ResolvedCampaign wiener = resolve_campaign(spec);
  const CampaignRunSummary one = RunCampaign(wiener, (tmp / "one").string(), {});
  const std::vector<CampaignFigure> titled = campaign_figures(wiener, one.rows);
  ASSERT_EQ(titled.size(), 1u);
  EXPECT_NE(titled[0].svg.find("dt 1, wiener (oracle prior);"), std::string::npos);
  EXPECT_NE(titled[0].svg.find("2 trials"), std::string::npos);
  EXPECT_NE(titled[0].svg.find(">short.txt<"), std::string::npos);
}

// campaign check: the restoration columns select the rows, ssim_mean has a standard error from
// ssim_sd and the trials, as rmse_mean has.
TEST(RestorationCampaign, CheckSelectsByRestorationAndComparesSsim) {
  const std::string results =
      "image,code,snr,restoration,regularization,prior,trials,ssim_mean,ssim_sd\n"
      "a.png,raskar,100,tikhonov,optimal,,10,0.95,0.01\n"
      "a.png,raskar,100,wiener,,oracle,10,0.97,0.01\n";
  CheckOptions options;
  options.k_standard_errors = 3;
  // SE sqrt(2 x 0.01^2 / 10) = 0.0045: 0.96 vs 0.97 is 2.2 SE, 0.95 vs 0.97 4.5 SE.
  const std::string close =
      "image,code,snr,restoration,prior,trials,ssim_mean,ssim_sd\n"
      "a.png,raskar,100,wiener,oracle,10,0.96,0.01\n";
  const CheckReport pass = CheckCampaignResults(results, "r.csv", close, "e.csv", options);
  ASSERT_EQ(pass.cases.size(), 1u);
  EXPECT_TRUE(pass.cases[0].passed) << pass.cases[0].message;
  const std::string far =
      "image,code,snr,restoration,regularization,trials,ssim_mean,ssim_sd\n"
      "a.png,raskar,100,tikhonov,optimal,10,0.97,0.01\n";
  const CheckReport fail = CheckCampaignResults(results, "r.csv", far, "e.csv", options);
  ASSERT_EQ(fail.cases.size(), 1u);
  EXPECT_FALSE(fail.cases[0].passed);
  EXPECT_NE(fail.cases[0].message.find("restoration=tikhonov regularization=optimal"),
            std::string::npos)
      << fail.cases[0].message;
  EXPECT_NE(fail.cases[0].message.find("ssim_mean 0.95, expected 0.97"), std::string::npos);
}

}  // namespace
}  // namespace fss
