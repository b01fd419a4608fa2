// The campaign library: specification, hash, product order, seeds, rows,
// journal and resume, shards and merge, regression checks, figures.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include "campaign/sha256.h"
#include "fss/campaign/check.h"
#include "fss/campaign/figures.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/memory_estimate.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;

// A 120 x 24 crop of data/camera.png, written into `dir`.
std::string write_crop(const fs::path& dir, const std::string& name = "crop.png", int x0 = 200) {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(120, 24, 1);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 240 + y, x0 + x);
  }
  const auto png = encode_png8(crop);
  const fs::path path = dir / name;
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

// A short code (L = 8), so that the crop fits its blur.
std::string write_short_code(const fs::path& dir) {
  const fs::path path = dir / "short.txt";
  test::write_file(path, "1 0 1 1 0 0 1 1\n");
  return path.string();
}

CampaignSpec small_spec(const test::TempDir& tmp) {
  CampaignSpec spec;
  spec.inputs = {write_crop(tmp.path())};
  spec.codes = {write_short_code(tmp.path()), "raskar"};
  spec.velocity = "0.5,1";
  spec.snr = "50:200:x2";
  spec.trials = 2;
  spec.seed = 7;
  return spec;
}

TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // Two blocks, and a message whose padding needs a block of its own.
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(ValueList, ListsAndRanges) {
  EXPECT_EQ(parse_value_list("3", "v").values, std::vector<double>({3}));
  EXPECT_EQ(parse_value_list("1,2.5,-1", "v").values, std::vector<double>({1, 2.5, -1}));
  const ValueList arithmetic = parse_value_list("0.1:0.5:0.1", "v");
  EXPECT_EQ(arithmetic.values, std::vector<double>({0.1, 0.2, 0.3, 0.4, 0.5}));
  EXPECT_FALSE(arithmetic.geometric);
  const ValueList geometric = parse_value_list("25:400:x2", "snr");
  EXPECT_EQ(geometric.values, std::vector<double>({25, 50, 100, 200, 400}));
  EXPECT_TRUE(geometric.geometric);
  EXPECT_EQ(parse_value_list("1,10:30:10", "v").values, std::vector<double>({1, 10, 20, 30}));
}

TEST(ValueList, RefusesMalformedItems) {
  for (const char* bad : {"", "a", "1,,2", "1:2", "2:1:1", "1:2:0", "0:8:x2", "1:8:x1", "1:8:xq",
                          "1:2:3:4", "nan", "1:1e9:1"}) {
    EXPECT_TRUE(
        test::throws_error([&] { parse_value_list(bad, "--snr"); }, ErrorKind::kUsage, {"--snr"}))
        << bad;
  }
}

TEST(Campaign, HashIsCanonical) {
  test::TempDir tmp;
  CampaignSpec a = small_spec(tmp);
  CampaignSpec b = a;
  b.snr = "50,100,200";  // the same values, spelled out
  b.snr = "50:200:x2";
  b.velocity = "0.5:1:0.5";
  const ResolvedCampaign ra = resolve_campaign(a), rb = resolve_campaign(b);
  EXPECT_EQ(ra.sha256, rb.sha256);
  b.trials = 3;
  EXPECT_NE(resolve_campaign(b).sha256, ra.sha256);
  // Rebuilt from its canonical form, without the files, it is the same.
  EXPECT_EQ(campaign_from_canonical_json(ra.canonical_json).sha256, ra.sha256);
}

TEST(Campaign, InputsAreFilesDirectoriesAndGlobs) {
  test::TempDir tmp;
  fs::create_directories(tmp / "images");
  write_crop(tmp / "images", "b.png", 100);
  write_crop(tmp / "images", "a.png", 150);
  test::write_file(tmp / "images" / "notes.txt", "not an image");
  CampaignSpec spec = small_spec(tmp);
  spec.inputs = {(tmp / "images").string(), (tmp / "images" / "*.png").string(),
                 (tmp / "images" / "a.png").string()};
  const ResolvedCampaign c = resolve_campaign(spec);
  std::vector<std::string> names;
  for (const CampaignImage& image : c.images) names.push_back(fs::path(image.name).filename());
  EXPECT_EQ(names, std::vector<std::string>({"a.png", "b.png"}));  // each once, sorted
  EXPECT_NE(c.images[0].sha256, c.images[1].sha256);
  spec.inputs = {(tmp / "images" / "*.jpg").string()};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"matches no PNG or TIFF file"}));
  spec.inputs = {(tmp / "missing.png").string()};
  EXPECT_TRUE(
      test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage, {"does not exist"}));
}

TEST(Campaign, ProductOrderIsStable) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  ASSERT_EQ(c.setting_count(), 1 * 2 * 1 * 2 * 1 * 3 * 1);
  const Setting s0 = setting_at(c, 0), s1 = setting_at(c, 1), s3 = setting_at(c, 3);
  EXPECT_EQ(s0.snr, 0);
  EXPECT_EQ(s1.snr, 1);  // snr varies faster than velocity
  EXPECT_EQ(s3.velocity, 1);
  EXPECT_EQ(setting_at(c, 6).code, 1);  // codes vary slower
}

TEST(Campaign, SeedsDependOnTheSettingNotItsPosition) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  const ResolvedCampaign c = resolve_campaign(spec);
  std::swap(spec.codes[0], spec.codes[1]);
  spec.velocity = "1,0.5";
  const ResolvedCampaign swapped = resolve_campaign(spec);
  std::set<std::uint64_t> seeds;
  for (long long i = 0; i < c.setting_count(); ++i) {
    const Setting s = setting_at(c, i);
    Setting t = s;
    t.code = 1 - s.code;
    t.velocity = 1 - s.velocity;
    EXPECT_EQ(setting_seed(c, s), setting_seed(swapped, t));
    seeds.insert(setting_seed(c, s));
  }
  EXPECT_EQ(seeds.size(), static_cast<std::size_t>(c.setting_count()));
  spec.seed = 8;
  EXPECT_NE(setting_seed(resolve_campaign(spec), setting_at(swapped, 0)),
            setting_seed(swapped, setting_at(swapped, 0)));
}

std::string cell(const ResultRow& row, const char* column) {
  return row[campaign_column_index(column)];
}

TEST(Campaign, SettingsThatCannotRunAreRowsWithAStatus) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.codes = {write_short_code(tmp.path()), "random", "raskar"};
  spec.modes = {ShutterMode::kAnalog};
  spec.snr = "-1,100";
  const ResolvedCampaign c = resolve_campaign(spec);
  const Image image = read_png(spec.inputs[0]);
  std::map<std::string, int> statuses;
  for (long long i = 0; i < c.setting_count(); ++i) {
    const ResultRow row = run_setting(c, setting_at(c, i), image, {});
    ASSERT_EQ(row.size(), campaign_columns().size());
    statuses[cell(row, "status")]++;
    if (cell(row, "status") != kStatusOk) EXPECT_FALSE(cell(row, "message").empty());
  }
  // snr -1: invalid; random in analog: code-refused; raskar (L = 52) on 120 columns: too narrow.
  EXPECT_EQ(statuses[kStatusInvalid], 6);
  EXPECT_EQ(statuses[kStatusCodeRefused], 2);
  EXPECT_EQ(statuses[kStatusTooNarrow], 2);
  EXPECT_EQ(statuses[kStatusOk], 2);
}

TEST(Campaign, RowsCarryProvenanceAndMatchSimulate) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const Image image = read_png(c.images[0].path);
  const Setting s = setting_at(c, 1);
  const ResultRow row = run_setting(c, s, image, {1, 0, "test-version"});
  SimulationOptions o = setting_options(c, s);
  const SimulationReport r = Simulate(o, image, c.codes[0].code);
  EXPECT_EQ(std::stod(cell(row, "rmse_mean")), r.trials.rmse_mean);
  EXPECT_EQ(std::stod(cell(row, "rmse_ci_sd")), r.trials.rmse_ci_sd);
  EXPECT_EQ(cell(row, "seed"), std::to_string(o.seed));
  EXPECT_EQ(cell(row, "image_sha256"), sha256_hex(test::read_file(c.images[0].path)));
  EXPECT_EQ(cell(row, "fssim_version"), "test-version");
  EXPECT_EQ(cell(row, "trials"), "2");
}

// The kernel cache changes nothing in the rows and computes each kernel
// once per code and velocity: the snr values share it.
TEST(Campaign, PlanCacheGivesTheRowsOfSimulateAlone) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const Image image = read_png(c.images[0].path);
  SimulationPlanCache plans;
  for (long long i = 0; i < c.setting_count(); ++i) {
    const Setting s = setting_at(c, i);
    EXPECT_EQ(run_setting(c, s, image, {1, 0, "v"}, &plans), run_setting(c, s, image, {1, 0, "v"}))
        << i;
  }
  // 2 codes x 2 velocities, 3 snr values each; the raskar code is too wide
  // for the crop and builds none.
  EXPECT_EQ(plans.built(), 2);
  EXPECT_EQ(plans.reused(), 4);
  const CampaignRunSummary summary = RunCampaign(c, (tmp / "out").string(), {});
  EXPECT_EQ(summary.plans_built, 2);
  EXPECT_EQ(summary.plans_reused, 4);
}

std::vector<std::vector<std::string>> csv_rows(const fs::path& path) {
  return parse_csv(test::read_file(path), path.string());
}

// Per-trial rows: each trial's seed and metrics; the setting's row is their
// mean; results.csv is the same as without them.
TEST(Campaign, PerTrialRowsAreTheTrialsOfEachSetting) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.trials = 3;
  const ResolvedCampaign plain = resolve_campaign(spec);
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  EXPECT_NE(c.sha256, plain.sha256);
  EXPECT_EQ(plain.canonical_json.find("per_trial"), std::string::npos);
  RunCampaign(plain, (tmp / "plain").string(), {});
  RunCampaign(c, (tmp / "trials").string(), {});
  EXPECT_FALSE(fs::exists(tmp / "plain" / kCampaignTrialsCsv));
  EXPECT_EQ(test::read_file(tmp / "plain" / kCampaignResultsCsv),
            test::read_file(tmp / "trials" / kCampaignResultsCsv));
  const auto results = csv_rows(tmp / "trials" / kCampaignResultsCsv);
  const auto trials = csv_rows(tmp / "trials" / kCampaignTrialsCsv);
  ASSERT_EQ(trials.front().size(), trial_columns().size());
  EXPECT_EQ(trials.front().back(), "ssim");
  const auto column = [](const char* name) {
    for (std::size_t i = 0; i < trial_columns().size(); ++i) {
      if (std::string(trial_columns()[i].name) == name) return i;
    }
    return std::size_t{0};
  };
  std::size_t next = 1;
  for (std::size_t r = 1; r < results.size(); ++r) {
    const ResultRow& row = results[r];
    if (row[campaign_column_index("status")] != kStatusOk) continue;
    double sum = 0.0;
    for (int t = 0; t < 3; ++t, ++next) {
      ASSERT_LT(next, trials.size());
      const auto& trial = trials[next];
      EXPECT_EQ(trial[column("code")], row[campaign_column_index("code")]);
      EXPECT_EQ(trial[column("snr")], row[campaign_column_index("snr")]);
      EXPECT_EQ(trial[column("trial")], std::to_string(t));
      EXPECT_EQ(trial[column("trial_seed")],
                std::to_string(std::stoull(row[campaign_column_index("seed")]) + t));
      sum += std::stod(trial[column("rmse")]);
    }
    EXPECT_EQ(std::stod(row[campaign_column_index("rmse_mean")]), sum / 3) << r;
  }
  EXPECT_EQ(next, trials.size());
  EXPECT_EQ(test::lines_of(test::read_file(tmp / "trials" / kCampaignTrialsJsonl)).size(),
            trials.size() - 1);
}

std::string trial_files_of(const fs::path& dir) {
  return test::read_file(dir / kCampaignTrialsCsv) + test::read_file(dir / kCampaignTrialsJsonl) +
         test::read_file(dir / kCampaignJournal);
}

TEST(Campaign, PerTrialRowsResumeAndMergeToTheBytesOfOneRun) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  RunCampaign(c, (tmp / "single").string(), {});
  // Resume from a journal cut in the middle of a line.
  const std::string journal = test::read_file(tmp / "single" / kCampaignJournal);
  fs::create_directories(tmp / "cut");
  test::write_file(tmp / "cut" / kCampaignJournal, journal.substr(0, journal.size() / 2));
  const CampaignRunSummary resumed = RunCampaign(c, (tmp / "cut").string(), {});
  EXPECT_GT(resumed.resumed, 0);
  EXPECT_GT(resumed.ran, 0);
  EXPECT_EQ(trial_files_of(tmp / "cut"), trial_files_of(tmp / "single"));
  // Shards and merge.
  std::vector<std::string> parts;
  for (int i = 1; i <= 3; ++i) {
    CampaignRunOptions options;
    options.shard = {i, 3};
    parts.push_back((tmp / ("part" + std::to_string(i))).string());
    RunCampaign(c, parts.back(), options);
  }
  MergeCampaignParts(parts, (tmp / "merged").string());
  EXPECT_EQ(trial_files_of(tmp / "merged"), trial_files_of(tmp / "single"));
  EXPECT_EQ(test::read_file(tmp / "merged" / kCampaignResultsCsv),
            test::read_file(tmp / "single" / kCampaignResultsCsv));
}

// The sensor (docs/method.md §10): the read noise is an axis, the other
// parts fixed; both are in the hash, the seeds and the rows, and a campaign
// without a sensor keeps the canonical form (hash, seeds) it had before.
TEST(Campaign, SensorIsInTheHashTheSettingsAndTheRows) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  const ResolvedCampaign plain = resolve_campaign(spec);
  EXPECT_FALSE(plain.has_sensor());
  EXPECT_EQ(plain.canonical_json.find("sensor"), std::string::npos);
  EXPECT_EQ(setting_description(plain, setting_at(plain, 0)).find("read_noise"), std::string::npos);

  spec.read_noise = "0,6";
  spec.sensor.dark_current_electrons_per_slot = 0.5;
  spec.sensor.adc_bits = 14;
  spec.sensor.adc_gain_electrons_per_count = 2.0;
  const ResolvedCampaign c = resolve_campaign(spec);
  EXPECT_TRUE(c.has_sensor());
  EXPECT_EQ(c.setting_count(), 2 * plain.setting_count());
  EXPECT_NE(c.sha256, plain.sha256);
  EXPECT_EQ(campaign_from_canonical_json(c.canonical_json).sha256, c.sha256);
  // The read noise varies fastest; the other values are those of plain's setting 0.
  const Setting quiet = setting_at(c, 0);
  const Setting noisy = setting_at(c, 1);
  EXPECT_EQ(setting_options(c, quiet).sensor.read_noise_electrons, 0.0);
  EXPECT_EQ(setting_options(c, noisy).sensor.read_noise_electrons, 6.0);
  EXPECT_EQ(setting_options(c, noisy).sensor.adc_bits, 14);
  EXPECT_EQ(setting_options(c, noisy).velocity_px_per_slot,
            setting_options(plain, setting_at(plain, 0)).velocity_px_per_slot);
  EXPECT_NE(setting_seed(c, quiet), setting_seed(c, noisy));
  const Image image = read_png(c.images[0].path);
  const ResultRow row = run_setting(c, noisy, image, {1, 0, "test-version"});
  EXPECT_EQ(cell(row, "status"), "ok") << cell(row, "message");
  EXPECT_EQ(cell(row, "read_noise"), "6");
  EXPECT_EQ(cell(row, "dark_current"), "0.5");
  EXPECT_EQ(cell(row, "full_well"), "");
  EXPECT_EQ(cell(row, "adc_bits"), "14");
  EXPECT_EQ(cell(row, "adc_gain"), "2");
  const SimulationReport r = Simulate(setting_options(c, noisy), image, c.codes[0].code);
  EXPECT_EQ(std::stod(cell(row, "predicted_rmse")), r.prediction.rmse);
  EXPECT_EQ(cell(row, "predicted_exact"), r.prediction.exact ? "true" : "false");

  spec.sensor.dark_current_electrons_per_slot = 0.25;  // a fixed part changes the hash
  EXPECT_NE(resolve_campaign(spec).sha256, c.sha256);
  spec.sensor.full_well_electrons = -3.0;
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"--full-well / \"full_well\" = -3: must be finite and > 0"}));
}

std::string results_of(const fs::path& dir) {
  return test::read_file(dir / kCampaignResultsCsv) + test::read_file(dir / kCampaignResultsJsonl) +
         test::read_file(dir / kCampaignManifest);
}

TEST(Campaign, ResumeRunsOnlyWhatIsMissingAndGivesTheSameBytes) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const CampaignRunSummary full = RunCampaign(c, (tmp / "full").string(), {});
  EXPECT_EQ(full.ran, c.setting_count());
  // A journal cut after three settings and in the middle of the fourth line,
  // as a kill -9 leaves it.
  const std::vector<std::string> lines =
      test::lines_of(test::read_file(tmp / "full" / kCampaignJournal));
  fs::create_directories(tmp / "cut");
  std::string cut = lines[0] + "\n" + lines[1] + "\n" + lines[2] + "\n" + lines[3] + "\n";
  cut += lines[4].substr(0, lines[4].size() / 2);
  test::write_file(tmp / "cut" / kCampaignJournal, cut);
  const CampaignRunSummary resumed = RunCampaign(c, (tmp / "cut").string(), {});
  EXPECT_EQ(resumed.resumed, 3);
  EXPECT_EQ(resumed.ran, c.setting_count() - 3);
  EXPECT_EQ(results_of(tmp / "cut"), results_of(tmp / "full"));
  EXPECT_EQ(test::read_file(tmp / "cut" / kCampaignJournal),
            test::read_file(tmp / "full" / kCampaignJournal));
  // Run again: nothing left to run.
  EXPECT_EQ(RunCampaign(c, (tmp / "cut").string(), {}).ran, 0);
}

// Settings side by side (several threads, one each) or one at a time give
// the same journal, results and trial rows, byte for byte; so does a memory
// limit that holds a single run only.
TEST(Campaign, SideBySideSettingsGiveTheBytesOfOneAtATime) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.per_trial = true;
  const ResolvedCampaign c = resolve_campaign(spec);
  CampaignRunOptions one;
  one.threads = 1;
  RunCampaign(c, (tmp / "one").string(), one);
  std::vector<long long> done;
  CampaignRunOptions side;
  side.threads = 3;
  side.progress = [&](const CampaignProgress& p) { done.push_back(p.done); };
  const CampaignRunSummary summary = RunCampaign(c, (tmp / "side").string(), side);
  // A limit above the largest run but below two of them side by side.
  const Image crop = read_png(c.images[0].path);
  std::size_t largest = kBaselineMemoryBytes;
  for (long long i = 0; i < c.setting_count(); ++i) {
    const Setting s = setting_at(c, i);
    SimulationOptions o = setting_options(c, s);
    o.threads = 1;
    try {
      largest =
          std::max(largest, estimate_run_memory_bytes({crop.width, crop.height, crop.channels}, o,
                                                      c.codes[s.code].code, false));
    } catch (const Error&) {  // too narrow for raskar
    }
  }
  CampaignRunOptions tight;
  tight.threads = 2;
  tight.max_memory_bytes = largest + (largest - kBaselineMemoryBytes) / 2;
  RunCampaign(c, (tmp / "tight").string(), tight);
  for (const char* file : {kCampaignJournal, kCampaignResultsCsv, kCampaignTrialsCsv}) {
    const std::string expected = test::read_file(tmp / "one" / file);
    EXPECT_EQ(test::read_file(tmp / "side" / file), expected) << file;
    EXPECT_EQ(test::read_file(tmp / "tight" / file), expected) << file;
  }
  // Progress counts up by one setting at a time, in order; each plan is built once.
  ASSERT_EQ(static_cast<long long>(done.size()), c.setting_count() + 1);
  for (std::size_t i = 0; i < done.size(); ++i) EXPECT_EQ(done[i], static_cast<long long>(i));
  EXPECT_EQ(summary.plans_built, 2);
  EXPECT_EQ(summary.plans_reused, 4);
}

TEST(Campaign, AChangedSpecificationIsRefused) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  RunCampaign(resolve_campaign(spec), (tmp / "out").string(), {});
  spec.trials = 3;
  EXPECT_TRUE(
      test::throws_error([&] { RunCampaign(resolve_campaign(spec), (tmp / "out").string(), {}); },
                         ErrorKind::kUsage, {"another campaign", "use a new output directory"}));
  CampaignRunOptions shard;
  shard.shard = {1, 2};
  spec.trials = 2;
  EXPECT_TRUE(test::throws_error(
      [&] { RunCampaign(resolve_campaign(spec), (tmp / "out").string(), shard); },
      ErrorKind::kUsage, {"shard 1/1", "not shard 1/2"}));
}

TEST(Campaign, TwoRunsIntoOneDirectoryAreRefused) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  fs::create_directories(tmp / "out");
  const int fd = ::open((tmp / "out" / ".campaign.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);  // as another process's run holds it
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "out").string(), {}); },
                                 ErrorKind::kUsage, {"in use by another fssim campaign"}));
  ::close(fd);
  EXPECT_EQ(RunCampaign(c, (tmp / "out").string(), {}).ran, c.setting_count());
}

TEST(Campaign, ShardsMergeToTheBytesOfOneRun) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  RunCampaign(c, (tmp / "single").string(), {});
  std::vector<std::string> parts;
  for (int i = 3; i >= 1; --i) {  // any order
    CampaignRunOptions options;
    options.shard = {i, 3};
    const std::string dir = (tmp / ("part" + std::to_string(i))).string();
    EXPECT_EQ(RunCampaign(c, dir, options).total, 4);
    parts.push_back(dir);
  }
  const std::vector<ResultRow> rows = MergeCampaignParts(parts, (tmp / "merged").string());
  EXPECT_EQ(static_cast<long long>(rows.size()), c.setting_count());
  EXPECT_EQ(results_of(tmp / "merged"), results_of(tmp / "single"));
  EXPECT_EQ(test::read_file(tmp / "merged" / kCampaignJournal),
            test::read_file(tmp / "single" / kCampaignJournal));
  // The merged directory is a finished run of the campaign.
  EXPECT_EQ(RunCampaign(c, (tmp / "merged").string(), {}).ran, 0);
}

TEST(Campaign, MergeRefusesForeignMissingDuplicateAndIncompleteParts) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  const ResolvedCampaign c = resolve_campaign(spec);
  const auto part = [&](const ResolvedCampaign& campaign, int i, int n, const std::string& name) {
    CampaignRunOptions options;
    options.shard = {i, n};
    RunCampaign(campaign, (tmp / name).string(), options);
    return (tmp / name).string();
  };
  const std::string p1 = part(c, 1, 2, "p1"), p2 = part(c, 2, 2, "p2");
  spec.seed = 99;
  const std::string foreign = part(resolve_campaign(spec), 2, 2, "foreign");
  const std::string out = (tmp / "merged").string();
  EXPECT_TRUE(test::throws_error(
      [&] {
        MergeCampaignParts({p1, foreign}, out);
      },
      ErrorKind::kUsage, {"belongs to campaign", "cannot be merged"}));
  EXPECT_TRUE(test::throws_error([&] { MergeCampaignParts({p1}, out); }, ErrorKind::kUsage,
                                 {"shard 2/2 is missing"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        MergeCampaignParts({p1, p1, p2}, out);
      },
      ErrorKind::kUsage, {"given more than once"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        MergeCampaignParts({p1, (tmp / "nothing").string()}, out);
      },
      ErrorKind::kUsage, {"not a campaign directory"}));
  // Part 2 with its last setting cut from the journal.
  const std::string journal = test::read_file(fs::path(p2) / kCampaignJournal);
  std::vector<std::string> lines = test::lines_of(journal);
  lines.pop_back();
  std::string shorter;
  for (const std::string& line : lines) shorter += line + "\n";
  test::write_file(fs::path(p2) / kCampaignJournal, shorter);
  EXPECT_TRUE(test::throws_error(
      [&] {
        MergeCampaignParts({p1, p2}, out);
      },
      ErrorKind::kUsage, {"is incomplete", "5 of 6"}));
  EXPECT_FALSE(fs::exists(fs::path(out) / kCampaignResultsCsv));
}

std::string lines_text(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// Shards 1/2 and 2/2 of `c` run into tmp/p1 and tmp/p2: their folders.
std::vector<std::string> run_two_shards(const ResolvedCampaign& c, const test::TempDir& tmp) {
  std::vector<std::string> parts;
  for (int i = 1; i <= 2; ++i) {
    CampaignRunOptions options;
    options.shard = {i, 2};
    parts.push_back((tmp / ("p" + std::to_string(i))).string());
    RunCampaign(c, parts.back(), options);
  }
  return parts;
}

// Shard 1/2 whose journal holds a row of shard 2/2 in place of one of its
// own: as many rows as it should have, but one setting missing in all.
TEST(Campaign, AJournalHoldingAnotherShardsRowIsRefused) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const std::vector<std::string> parts = run_two_shards(c, tmp);
  const fs::path journal = fs::path(parts[0]) / kCampaignJournal;
  std::vector<std::string> first = test::lines_of(test::read_file(journal));
  const std::vector<std::string> second =
      test::lines_of(test::read_file(fs::path(parts[1]) / kCampaignJournal));
  first[2] = second[1];  // setting 1 (shard 2/2) on line 3, where setting 2 was
  test::write_file(journal, lines_text(first));
  const std::string out = (tmp / "merged").string();
  EXPECT_TRUE(test::throws_error([&] { MergeCampaignParts(parts, out); }, ErrorKind::kRuntime,
                                 {journal.string(), "line 3", "setting 1", "shard 2/2"}));
  EXPECT_FALSE(fs::exists(out));
  CampaignRunOptions options;
  options.shard = {1, 2};
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, parts[0], options); }, ErrorKind::kRuntime,
                                 {journal.string(), "line 3"}));
}

// A row of the right shard written under another of its settings' index
// (setting 2's row as setting 0's) is refused by merge and by a resume.
TEST(Campaign, AJournalRowUnderAnotherSettingsIndexIsRefused) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const std::vector<std::string> parts = run_two_shards(c, tmp);
  const fs::path journal = fs::path(parts[0]) / kCampaignJournal;
  std::vector<std::string> lines = test::lines_of(test::read_file(journal));
  ASSERT_GE(lines.size(), 3u);
  const std::size_t at = lines[2].find("\"index\":2");
  ASSERT_NE(at, std::string::npos) << lines[2];
  lines[1] = lines[2];
  lines[1].replace(at, 9, "\"index\":0");
  test::write_file(journal, lines_text(lines));
  const std::string out = (tmp / "merged").string();
  EXPECT_TRUE(test::throws_error([&] { MergeCampaignParts(parts, out); }, ErrorKind::kRuntime,
                                 {journal.string(), "setting 0", "differs"}));
  EXPECT_FALSE(fs::exists(out));
  CampaignRunOptions options;
  options.shard = {1, 2};
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, parts[0], options); }, ErrorKind::kRuntime,
                                 {journal.string(), "setting 0"}));
}

// fssim writes a journal's header whole (renamed into place): a journal.jsonl
// without a complete header line is not fssim's, and is never removed.
TEST(Campaign, AJournalWithoutACompleteHeaderIsRefusedNotRemoved) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  CampaignRunOptions second;
  second.shard = {2, 2};
  const std::string p2 = (tmp / "p2").string();
  RunCampaign(c, p2, second);
  const std::string header = test::lines_of(test::read_file(fs::path(p2) / kCampaignJournal))[0];
  for (const std::string& text : {std::string(), header, std::string("my notes")}) {
    const fs::path dir = tmp / "dir";
    fs::create_directories(dir);
    test::write_file(dir / kCampaignJournal, text);
    EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, dir.string(), {}); }, ErrorKind::kRuntime,
                                   {"not an fssim campaign journal"}));
    EXPECT_TRUE(test::throws_error(
        [&] {
          MergeCampaignParts({dir.string(), p2}, "merged");
        },
        ErrorKind::kRuntime, {"not an fssim campaign journal"}));
    EXPECT_EQ(test::read_file(dir / kCampaignJournal), text);
    fs::remove_all(dir);
  }
  // Nor is a directory of that name, even empty.
  fs::create_directories(tmp / "dir" / kCampaignJournal);
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "dir").string(), {}); },
                                 ErrorKind::kRuntime, {"not an fssim campaign journal"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        MergeCampaignParts({(tmp / "dir").string(), p2}, "m");
      },
      ErrorKind::kRuntime, {"not an fssim campaign journal"}));
  EXPECT_TRUE(fs::is_directory(tmp / "dir" / kCampaignJournal));
}

TEST(Campaign, JournalLinesNestedTooDeeplyAreRefused) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const fs::path dir = tmp / "out";
  RunCampaign(c, dir.string(), {});
  std::vector<std::string> lines = test::lines_of(test::read_file(dir / kCampaignJournal));
  lines[1] = "{\"index\": 0, \"row\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  test::write_file(dir / kCampaignJournal, lines_text(lines));
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, dir.string(), {}); }, ErrorKind::kRuntime,
                                 {"line 2", "nested deeper than 64 levels"}));
}

TEST(Campaign, AForgedSpecificationIsRefused) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string json = c.canonical_json;
    json.replace(json.find(from), from.size(), to);
    return json;
  };
  for (const std::string& json :
       {replaced("\"numerical\"", "\"digital\""),
        replaced("\"noise\":\"poisson\"", "\"noise\":\"x\""),
        replaced("\"modes\":[\"numerical\"]", "\"modes\":[]"),
        replaced("\"trials\":2", "\"trials\":-4"),
        replaced("\"modes\"",
                 "\"deep\":" + std::string(200, '[') + std::string(200, ']') + ",\"modes\"")}) {
    EXPECT_TRUE(test::throws_error([&] { campaign_from_canonical_json(json); }, ErrorKind::kRuntime,
                                   {"malformed campaign specification"}))
        << json;
  }
}

TEST(Campaign, AFailedRunLeavesNoDirectoryItCreated) {
  test::TempDir tmp;
  const CampaignSpec spec = small_spec(tmp);
  const ResolvedCampaign c = resolve_campaign(spec);
  write_crop(tmp.path(), "crop.png", 300);  // the image changes after the campaign resolved
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "new/a/b").string(), {}); },
                                 ErrorKind::kRuntime, {"changed since the campaign started"}));
  EXPECT_FALSE(fs::exists(tmp / "new"));
  fs::create_directories(tmp / "old");
  EXPECT_TRUE(test::throws_error([&] { RunCampaign(c, (tmp / "old/c").string(), {}); },
                                 ErrorKind::kRuntime));
  EXPECT_TRUE(test::list_directory(tmp / "old").empty());
}

TEST(Campaign, ANameThatIsNotUtf8IsRefused) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.inputs = {write_crop(tmp.path(), "caf\xe9.png")};
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"image '", "' is not valid UTF-8"}));
}

TEST(Campaign, AnOutputThatIsAnInputIsRefused) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  const fs::path out = tmp / "out";
  fs::create_directories(out);
  // A code file named as an output, and the campaign file as campaign.json.
  test::write_file(out / kCampaignResultsCsv, "1 0 1 1 0 0 1 1\n");
  spec.codes = {(out / kCampaignResultsCsv).string()};
  EXPECT_TRUE(test::throws_error(
      [&] { RunCampaign(resolve_campaign(spec), out.string(), {}); }, ErrorKind::kUsage,
      {"would replace the input", (out / kCampaignResultsCsv).string()}));
  EXPECT_EQ(test::read_file(out / kCampaignResultsCsv), "1 0 1 1 0 0 1 1\n");
  spec = small_spec(tmp);
  test::write_file(out / kCampaignManifest, "{}");
  CampaignRunOptions options;
  options.inputs = {(out / kCampaignManifest).string()};
  EXPECT_TRUE(
      test::throws_error([&] { RunCampaign(resolve_campaign(spec), out.string(), options); },
                         ErrorKind::kUsage, {"would replace the input"}));
  EXPECT_EQ(test::read_file(out / kCampaignManifest), "{}");
  EXPECT_FALSE(fs::exists(out / kCampaignJournal));
}

const char kResults[] =
    "image,code,mode,velocity,snr,dt,trials,rmse_mean,rmse_sd,status\n"
    "data/camera.png,raskar,numerical,1,100,1,20,2.36,0.016,ok\n"
    "data/camera.png,mip,numerical,1,100,1,20,2.2,0.012,ok\n";

TEST(Check, PassesWithinTolerancesAndReportsDeviations) {
  CheckOptions options;
  options.k_standard_errors = 3;
  // raskar: 2.36 vs 2.352, SE sqrt(0.016^2/20 + 0.013^2/12) = 0.0048: 1.7 SE.
  // mip: 2.2 vs 2.116, 17 SE.
  const std::string expected =
      "image,code,mode,velocity,snr,dt,trials,rmse_mean,rmse_sd\n"
      "camera.png,raskar,numerical,1,100,1,12,2.352,0.013\n"
      "camera.png,mip,numerical,1.0,100,1,12,2.116,0.014\n"
      "camera.png,sinc,numerical,1,100,1,12,1.354,0.007\n";
  const CheckReport report = CheckCampaignResults(kResults, "r.csv", expected, "e.csv", options);
  ASSERT_EQ(report.cases.size(), 3u);
  EXPECT_TRUE(report.cases[0].passed) << report.cases[0].message;
  EXPECT_FALSE(report.cases[1].passed);
  EXPECT_NE(report.cases[1].message.find("code=mip"), std::string::npos);
  EXPECT_NE(report.cases[1].message.find("rmse_mean 2.2, expected 2.116"), std::string::npos);
  EXPECT_FALSE(report.cases[2].passed);
  EXPECT_NE(report.cases[2].message.find("no such row"), std::string::npos);
  EXPECT_EQ(report.failures(), 2);
  const std::string xml = check_junit_xml(report, "suite");
  EXPECT_NE(xml.find("tests=\"3\" failures=\"2\""), std::string::npos);
  // With a loose absolute tolerance mip passes too.
  options.abs_tolerance = 0.1;
  EXPECT_EQ(CheckCampaignResults(kResults, "r", expected, "e", options).failures(), 1);
  // Without options, the default rules (tests/campaign/check_test.cpp): a file passes itself.
  EXPECT_EQ(CheckCampaignResults(kResults, "r", kResults, "e", {}).failures(), 0);
}

TEST(Check, RefusesMalformedInput) {
  EXPECT_TRUE(test::throws_error(
      [&] {
        CheckCampaignResults(kResults, "r.csv", "code,predicted_rmse\nraskar,1\n", "e.csv", {});
      },
      ErrorKind::kUsage, {"predicted_rmse", "r.csv"}));
  EXPECT_TRUE(test::throws_error([&] { parse_csv("a,b\n1\n", "x.csv"); }, ErrorKind::kUsage,
                                 {"x.csv", "line 2"}));
  EXPECT_TRUE(test::throws_error([&] { parse_csv("a\n\"1\n", "x.csv"); }, ErrorKind::kUsage,
                                 {"not closed"}));
}

TEST(Check, RefusesExpectationsWithoutSettingColumns) {
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignResults(kResults, "r.csv", "rmse_mean\n2.36\n2.2\n", "e.csv", {}); },
      ErrorKind::kUsage, {"'e.csv' has none of the setting columns"}));
}

// A check that would check nothing, or the wrong rows, is refused: a
// misspelt or repeated column, no quantity, settings matching two rows.
TEST(Check, RefusesExpectationsThatCheckNothingOrTheWrongRows) {
  CheckOptions abs;  // EXPECTED without rmse_sd: a given tolerance
  abs.abs_tolerance = 0.0;
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignResults(kResults, "r.csv", "code,rmse_maen\nraskar,9\n", "e.csv", {}); },
      ErrorKind::kUsage, {"'e.csv': column 'rmse_maen' is not a column of campaign results"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        CheckCampaignResults(kResults, "r.csv", "code,code,rmse_mean\nraskar,raskar,2.36\n",
                             "e.csv", {});
      },
      ErrorKind::kUsage, {"column 'code' appears twice"}));
  EXPECT_TRUE(test::throws_error(
      [&] { CheckCampaignResults(kResults, "r.csv", "code,velocity\nraskar,1\n", "e.csv", {}); },
      ErrorKind::kUsage, {"'e.csv' has no quantity to compare"}));
  EXPECT_TRUE(test::throws_error(
      [&] {
        CheckCampaignResults(kResults, "r.csv", "image,rmse_mean\ndata/camera.png,2.36\n", "e.csv",
                             abs);
      },
      ErrorKind::kUsage, {"matches lines 2 and 3 of 'r.csv'"}));
}

// The sensor's fields are named as the options and keys that set them, and
// a gain without an ADC is refused as the command line refuses it.
TEST(Campaign, SensorFieldsAreNamedAndAGainNeedsAnAdc) {
  test::TempDir tmp;
  CampaignSpec spec = small_spec(tmp);
  spec.sensor.adc_gain_electrons_per_count = 5.0;
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"--adc-gain / \"adc_gain\" = 5: needs --adc-bits"}));
  spec = small_spec(tmp);
  spec.sensor.dark_current_electrons_per_slot = 1e308;
  EXPECT_TRUE(test::throws_error([&] { resolve_campaign(spec); }, ErrorKind::kUsage,
                                 {"--dark-current / \"dark_current\" = 1e+308: must lie in"}));
  spec = small_spec(tmp);
  spec.read_noise = "1e300";
  const ResolvedCampaign c = resolve_campaign(spec);
  const std::vector<ResultRow> rows = RunCampaign(c, (tmp / "out").string(), {}).rows;
  ASSERT_FALSE(rows.empty());
  const std::string& message = rows[0][static_cast<std::size_t>(campaign_column_index("message"))];
  EXPECT_NE(message.find("--read-noise / \"read_noise\" = 1e+300"), std::string::npos) << message;
}

// A campaign file that is not JSON: the parser's words, without its tag.
TEST(Campaign, JsonErrorsShowNoLibraryTag) {
  const std::optional<Error> error =
      test::error_of([] { parse_campaign_file("{\"trials\": x}", "f.json"); });
  ASSERT_TRUE(error.has_value());
  const std::string message = error->what();
  EXPECT_NE(message.find("campaign file 'f.json': parse error at line 1"), std::string::npos)
      << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
}

TEST(Check, MessagesNameTheOptionsAndAreOneLineWithoutNaN) {
  CheckOptions options;
  options.abs_tolerance = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(
      test::throws_error([&] { CheckCampaignResults(kResults, "r", kResults, "e", options); },
                         ErrorKind::kUsage, {"--abs = inf"}));
  options = {};
  options.k_standard_errors = -1;
  EXPECT_TRUE(
      test::throws_error([&] { CheckCampaignResults(kResults, "r", kResults, "e", options); },
                         ErrorKind::kUsage, {"--k-se = -1"}));
  CampaignSpec spec;
  spec.inputs = {"a.png"};
  spec.codes = {"raskar"};
  spec.rmse_margin_columns = -5;
  std::string error;
  EXPECT_FALSE(spec.IsValid(&error));
  EXPECT_NE(error.find("--rmse-margin / \"rmse_margin\" = -5"), std::string::npos) << error;
  // A cell holding a line break, and a result with no number.
  const std::string results = "code,rmse_mean,status\n\"rask\nar\",,\"o\nk\"\nmip,inf,okay\n";
  const std::string expected = "code,rmse_mean,status\n\"rask\nar\",2,ok\nmip,2,ok\n";
  CheckOptions abs;  // no rmse_sd: a given tolerance, not the default k standard errors
  abs.abs_tolerance = 0.0;
  const CheckReport report = CheckCampaignResults(results, "r", expected, "e", abs);
  ASSERT_EQ(report.cases.size(), 4u);
  for (const CheckCase& c : report.cases) {
    EXPECT_FALSE(c.passed);
    EXPECT_EQ(c.message.find('\n'), std::string::npos) << c.message;
    EXPECT_EQ(c.message.find("nan"), std::string::npos) << c.message;
  }
}

TEST(Figures, OneFigurePerSweptQuantityAndFixedSetting) {
  test::TempDir tmp;
  const ResolvedCampaign c = resolve_campaign(small_spec(tmp));
  const CampaignRunSummary run = RunCampaign(c, (tmp / "out").string(), {});
  const std::vector<CampaignFigure> figures = campaign_figures(c, run.rows);
  // velocity (2 values): one per snr (3); snr (3 values, log axis): one per velocity (2).
  ASSERT_EQ(figures.size(), 5u);
  EXPECT_EQ(figures[0].name, "rmse_vs_velocity__crop__numerical__snr50");
  EXPECT_EQ(figures[3].name, "rmse_vs_snr__crop__numerical__v0.5");
  for (const CampaignFigure& f : figures) {
    EXPECT_GT(f.png.size(), 1000u);
    EXPECT_NE(f.svg.find("<svg"), std::string::npos);
  }
  EXPECT_NE(figures[3].svg.find(">200</text>"), std::string::npos);  // the log snr axis
  EXPECT_NE(figures[3].svg.find("2 trials"), std::string::npos);
}

}  // namespace
}  // namespace fss
