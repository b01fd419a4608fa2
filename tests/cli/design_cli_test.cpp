// End-to-end tests of `fssim code generate | analyze | optimize` and
// `fssim sweep`, and unit tests of the command line's range syntax.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"
#include "range.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_fssim;
using ::testing::HasSubstr;
using ::testing::StartsWith;

using test::quote;

std::string camera() { return quote(test::source_path("data/camera.png")); }

using test::lines_of;

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  if (!line.empty() && line.back() == separator) fields.push_back("");
  return fields;
}

// The number after "label: " on the line that starts with it.
double value_after(const std::string& out, const std::string& label) {
  for (const std::string& line : lines_of(out)) {
    if (line.rfind(label + ": ", 0) == 0) return std::stod(line.substr(label.size() + 2));
  }
  ADD_FAILURE() << "no line '" << label << ": ...' in:\n" << out;
  return std::nan("");
}

void expect_one_error_line(const CommandResult& result) {
  const std::vector<std::string> lines = lines_of(result.err);
  EXPECT_EQ(lines.size(), 1u) << "stderr:\n" << result.err;
  if (!lines.empty()) EXPECT_THAT(lines[0], StartsWith("fssim: error:"));
  EXPECT_LE(result.err.size(), 250u) << result.err;
}

// ---------------------------------------------------------------------------
// Range syntax.

TEST(Range, SingleValue) {
  EXPECT_EQ(fssim::parse_range("1.5", "--velocity"), std::vector<double>{1.5});
  EXPECT_EQ(fssim::parse_range("-2", "--velocity"), std::vector<double>{-2.0});
  EXPECT_EQ(fssim::parse_range("+3", "--velocity"), std::vector<double>{3.0});
}

TEST(Range, InclusiveStopWithinHalfAStep) {
  EXPECT_EQ(fssim::parse_range("0.25:2:0.25", "--velocity"),
            (std::vector<double>{0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0}));
  // 0.1 steps do not add up to 0.3 exactly; the stop is still included.
  const std::vector<double> tenths = fssim::parse_range("0.1:0.3:0.1", "--snr");
  ASSERT_EQ(tenths.size(), 3u);
  EXPECT_DOUBLE_EQ(tenths[2], 0.1 + 2 * 0.1);
  // A stop that is not on the grid: the last value stays below stop + step / 2.
  EXPECT_EQ(fssim::parse_range("0:1:0.3", "--velocity"),
            (std::vector<double>{0.0, 0.3, 0.6, 0.8999999999999999}));
  EXPECT_EQ(fssim::parse_range("5:5:1", "--snr"), std::vector<double>{5.0});
  EXPECT_EQ(fssim::parse_range("-1:1:1", "--velocity"), (std::vector<double>{-1.0, 0.0, 1.0}));
}

TEST(Range, ErrorsNameTheOptionAndTheRule) {
  struct Case {
    const char* text;
    const char* rule;
  };
  const Case cases[] = {
      {"abc", "finite number"},      {"nan", "finite number"},
      {"inf", "finite number"},      {"", "finite number"},
      {"1:2", "three parts"},        {"1:2:3:4", "three parts"},
      {"0:1:0", "step must be > 0"}, {"0:1:-0.5", "step must be > 0"},
      {"0:nan:0.5", "finite"},       {"0:1:inf", "finite"},
      {"2:1:0.5", "stop"},           {"0:1:0.00001", "more than 10000"},
      {"1:x:1", "finite"},
  };
  for (const Case& c : cases) {
    EXPECT_TRUE(test::throws_error([&] { fssim::parse_range(c.text, "--velocity"); },
                                   ErrorKind::kUsage, {"--velocity", c.rule}))
        << "'" << c.text << "'";
  }
  // 10000 values is the limit, not an error.
  EXPECT_EQ(fssim::parse_range("1:10000:1", "--snr").size(), 10000u);
}

// ---------------------------------------------------------------------------
// code generate.

class CodeCli : public ::testing::Test {
 protected:
  test::TempDir dir_;
};

TEST_F(CodeCli, GenerateWritesAFileTheSimulatorAccepts) {
  const fs::path file = dir_ / "sinc52.txt";
  const CommandResult r =
      run_fssim("code generate sinc --length 52 --velocity 1 -o " + quote(file));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, HasSubstr("written to"));
  const ShutterCode code = load_code(file.string());
  EXPECT_EQ(code.gains, generate_sinc_code(52, 1.0, 1.0));  // shortest exact decimals
  EXPECT_THAT(test::read_file(file), StartsWith("# sinc code, L = 52"));
  EXPECT_EQ(test::list_directory(dir_.path()), std::vector<std::string>{"sinc52.txt"});

  const CommandResult sim = run_fssim("--input " + camera() + " --code " + quote(file) +
                                      " --noise none --outdir " + quote(dir_ / "out"));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  // Noise-free RMSE of the paper's sinc code on camera.png (docs/method.md §6: 0.357).
  const double rmse = std::stod(lines_of(sim.out).at(0).substr(6));
  EXPECT_NEAR(rmse, 0.357, 0.002);
}

TEST_F(CodeCli, GenerateToStandardOutput) {
  const CommandResult r = run_fssim("code generate mip --length 30 --velocity 0.5 --dt 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parse_code_text(r.out, "stdout").gains, generate_mip_code(30, 1.0, 1.0));

  const CommandResult random = run_fssim("code generate random --length 20 --seed 3 --analog");
  ASSERT_EQ(random.exit_code, 0) << random.err;
  EXPECT_EQ(parse_code_text(random.out, "stdout").gains, generate_random_code(20, 3, true));
  EXPECT_THAT(random.out, HasSubstr("seed 3"));

  const CommandResult snapshot = run_fssim("code generate snapshot -L 4");
  ASSERT_EQ(snapshot.exit_code, 0) << snapshot.err;
  EXPECT_EQ(parse_code_text(snapshot.out, "stdout").gains,
            (std::vector<double>{1.0, 0.0, 0.0, 0.0}));
  const CommandResult accumulation = run_fssim("code generate accumulation -L 3");
  EXPECT_EQ(parse_code_text(accumulation.out, "stdout").gains,
            (std::vector<double>{1.0, 1.0, 1.0}));
}

// ---------------------------------------------------------------------------
// code analyze.

TEST_F(CodeCli, AnalyzePrintsTheFiguresOfMerit) {
  const CommandResult r = run_fssim("code analyze raskar");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, StartsWith("Code: raskar (L = 52)\n"));
  EXPECT_DOUBLE_EQ(value_after(r.out, "Sum of gains"), 26.0);
  EXPECT_DOUBLE_EQ(value_after(r.out, "Sum of squares"), 26.0);
  EXPECT_DOUBLE_EQ(value_after(r.out, "Normalized L1 norm"), 26.0);
  EXPECT_THAT(r.out, HasSubstr("\nInvertible: yes\n"));
  EXPECT_THAT(r.out, HasSubstr("Min |K| on the band: "));
  const CodeAnalysis a =
      analyze_code(*builtin_code("raskar"), 1.0, 1.0, 100.0, ShutterMode::kNumerical);
  EXPECT_NEAR(value_after(r.out, "SNR at level 100"), a.snr_level100, 1e-6);
  EXPECT_NEAR(value_after(r.out, "Snapshot SNR at level 100"), 84.932180, 1e-6);
  EXPECT_NEAR(value_after(r.out, "Ratio to the snapshot"), a.ratio_to_snapshot, 1e-6);
  EXPECT_NEAR(value_after(r.out, "Bound on the SNR at level 100 (any code, any length)"), 85.745378,
              1e-6);
}

TEST_F(CodeCli, AnalyzeOnTheSimulatorsGridMatchesItsPrediction) {
  // report.json's snr_level100 of a real run against `code analyze --grid 2 Wa`.
  const CommandResult sim =
      run_fssim("--input " + camera() + " --code mip --velocity 0.8 --snr 50 --outdir " +
                quote(dir_ / "out"));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const nlohmann::json report = nlohmann::json::parse(test::read_file(dir_ / "out/report.json"));
  const int grid = report["geometry"]["mirror_width"];
  EXPECT_EQ(grid, 920);
  const fs::path json = dir_ / "analysis.json";
  const CommandResult r = run_fssim("code analyze mip --velocity 0.8 --snr 50 --grid " +
                                    std::to_string(grid) + " --json " + quote(json));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double predicted = report["prediction"]["snr_level100"];
  EXPECT_NEAR(value_after(r.out, "SNR at level 100"), predicted, 1e-6);
  EXPECT_THAT(r.out, HasSubstr("920-point DFT grid"));
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(json));
  EXPECT_NEAR(analysis["analysis"]["snr_level100"].get<double>(), predicted, 1e-9 * predicted);
  EXPECT_NEAR(analysis["analysis"]["m"].get<double>(), report["prediction"]["m"].get<double>(),
              1e-12);
  EXPECT_DOUBLE_EQ(analysis["analysis"]["q"].get<double>(), report["prediction"]["q"]);
  EXPECT_EQ(analysis["code"]["length"], 52);
  EXPECT_EQ(analysis["parameters"]["grid_points"], 920);
  EXPECT_EQ(analysis["parameters"]["mode"], "numerical");
}

TEST_F(CodeCli, AnalyzeANonInvertibleCode) {
  const fs::path json = dir_ / "a.json";
  const CommandResult r = run_fssim("code analyze accumulation --json " + quote(json));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Invertible: no"));
  EXPECT_THAT(r.out, HasSubstr("): infinite\n"));
  EXPECT_EQ(value_after(r.out, "SNR at level 100"), 0.0);
  const nlohmann::json analysis = nlohmann::json::parse(test::read_file(json));
  EXPECT_TRUE(analysis["analysis"]["m"].is_null());
  EXPECT_EQ(analysis["analysis"]["invertible"], false);
}

// The sensor options: off, nothing of the sensor is printed; on, the
// analysis counts the readouts (docs/method.md §10).
TEST_F(CodeCli, AnalyzeWithReadNoise) {
  const CommandResult plain = run_fssim("code analyze raskar --snr 20 --json -");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const nlohmann::json p = nlohmann::json::parse(plain.out);
  EXPECT_FALSE(p["parameters"].contains("sensor"));
  EXPECT_FALSE(p["analysis"].contains("effective_q"));
  const CommandResult text = run_fssim("code analyze raskar --snr 20 --read-noise 10");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("\nSensor: read noise 10 e- RMS per readout (4 "
                                  "photo-electrons per gray level per slot)\n"));
  EXPECT_DOUBLE_EQ(value_after(text.out, "Readouts"), 26.0);
  // Q_eff = 26 (1 + 10^2 / 20^2) = 32.5
  EXPECT_NEAR(value_after(text.out, "Effective Q (photon noise and readouts)"), 32.5, 1e-6);
  const CommandResult json = run_fssim(
      "code analyze raskar --snr 20 --read-noise 10 --dark-current 0.5 --adc-bits 12 "
      "--adc-gain 2 --mode analog --json -");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["parameters"]["sensor"]["read_noise_electrons"], 10.0);
  EXPECT_EQ(j["parameters"]["sensor"]["dark_current_electrons_per_slot"], 0.5);
  EXPECT_EQ(j["parameters"]["sensor"]["adc_bits"], 12);
  EXPECT_EQ(j["parameters"]["sensor"]["adc_gain_electrons_per_count"], 2.0);
  EXPECT_EQ(j["analysis"]["readouts"], 1.0);
  // v_r = 100 + 0.5 * 52 + 4 / 12
  EXPECT_NEAR(j["analysis"]["readout_variance_electrons2"].get<double>(), 126.0 + 1.0 / 3.0, 1e-12);
  SensorModel sensor;
  sensor.read_noise_electrons = 10.0;
  sensor.dark_current_electrons_per_slot = 0.5;
  sensor.adc_bits = 12;
  sensor.adc_gain_electrons_per_count = 2.0;
  const CodeAnalysis a =
      analyze_code(*builtin_code("raskar"), 1.0, 1.0, 20.0, ShutterMode::kAnalog, 0, sensor);
  EXPECT_DOUBLE_EQ(j["analysis"]["snr_level100"].get<double>(), a.snr_level100);
  EXPECT_DOUBLE_EQ(j["analysis"]["effective_q"].get<double>(), a.effective_q);
}

// The test, on the command line: the SNR at level 100 falls with the
// read noise, faster in the numerical mode (26 weighted frames read) than in
// the analog one (one readout).
TEST_F(CodeCli, AnalyzeSnrFallsWithReadNoiseFasterWhenNumerical) {
  auto snr = [](const std::string& mode, int read_noise) {
    const CommandResult r = run_fssim("code analyze raskar --snr 20 --mode " + mode +
                                      " --read-noise " + std::to_string(read_noise) + " --json -");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out)["analysis"]["snr_level100"].get<double>();
  };
  const double numerical0 = snr("numerical", 0), analog0 = snr("analog", 0);
  double last_numerical = numerical0, last_analog = analog0;
  for (const int r : {5, 10, 20}) {
    const double numerical = snr("numerical", r), analog = snr("analog", r);
    EXPECT_LT(numerical, last_numerical) << r;
    EXPECT_LT(analog, last_analog) << r;
    EXPECT_LT(numerical / numerical0, analog / analog0) << r;
    last_numerical = numerical;
    last_analog = analog;
  }
}

TEST_F(CodeCli, AnalyzeWarnsWhenTheAdcClipsTheLevel100Readout) {
  const CommandResult r = run_fssim("code analyze snapshot --adc-bits 8 --adc-gain 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 100 * 100 photo-electrons against 255 counts of 1 e-.
  EXPECT_THAT(r.err, HasSubstr("fssim: warning: a level-100 readout of 10000 e- passes the "
                               "ADC's top of 255 e-"));
  const CommandResult fine = run_fssim("code analyze snapshot --adc-bits 16 --adc-gain 1");
  EXPECT_EQ(fine.err, "");
}

// ---------------------------------------------------------------------------
// code optimize.

TEST_F(CodeCli, OptimizeUnderReadNoise) {
  const fs::path file = dir_ / "best.txt";
  const CommandResult r =
      run_fssim("code optimize -L 52 -v 1 --mode analog --snr 20 --read-noise 20 --restarts 8 -o " +
                quote(file));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("\nSensor: read noise 20 e- RMS per readout; snr 20 (4 "
                               "photo-electrons per gray level per slot)\n"));
  const std::string text = test::read_file(file);
  EXPECT_THAT(text, HasSubstr("# sensor: read noise 20 e- RMS per readout\n"));
  const ShutterCode code = load_code(file.string());
  SensorModel sensor;
  sensor.read_noise_electrons = 20.0;
  // Better under that read noise than the snapshot, the optimum without it
  // (with 8 restarts by 0.2%; the default 24 find 3.9%).
  EXPECT_GT(analyze_code(code, 1.0, 1.0, 20.0, ShutterMode::kAnalog, 0, sensor).snr_level100,
            1.001 * analyze_code(*builtin_code("snapshot"), 1.0, 1.0, 20.0, ShutterMode::kAnalog, 0,
                                 sensor)
                        .snr_level100);
  // Without a sensor option nothing about a sensor is written.
  const CommandResult plain = run_fssim("code optimize -L 8 -v 1 --restarts 1 -o -");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_THAT(plain.out, ::testing::Not(HasSubstr("sensor")));
}

TEST_F(CodeCli, OptimizeWritesACodeThatBeatsThePaperCodes) {
  const fs::path file = dir_ / "best.txt";
  // Under AddressSanitizer 2 restarts: the snapshot, the best paper code, is a start anyway.
  const CommandResult r = run_fssim("code optimize --length 52 --velocity 1 --mode analog -o " +
                                    quote(file) + (test::kAddressSanitizer ? " --restarts 2" : ""));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, StartsWith("Optimized analog code: L = 52, velocity 1, dt 1\n"));
  EXPECT_THAT(r.out, HasSubstr("(not admissible: random, mip, sinc)"));
  EXPECT_THAT(r.out, HasSubstr("Code written to"));
  const ShutterCode code = load_code(file.string());
  ASSERT_EQ(code.length(), 52);
  const CodeAnalysis ours =
      analyze_code(code, 1.0, 1.0, 100.0, ShutterMode::kAnalog);  // analog-admissible
  for (const char* name : {"snapshot", "accumulation", "raskar"}) {
    EXPECT_GE(ours.snr_level100,
              analyze_code(*builtin_code(name), 1.0, 1.0, 100.0, ShutterMode::kAnalog).snr_level100)
        << name;
  }
  // The optimized code runs through the simulator.
  const CommandResult sim = run_fssim("--input " + camera() + " --code " + quote(file) +
                                      " --mode analog --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
}

TEST_F(CodeCli, OptimizeBinaryWithALightBudget) {
  const CommandResult r =
      run_fssim("code optimize -L 20 -v 0.9 --binary --min-light 8 --restarts 3 --seed 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("light >= 8 slots"));
  EXPECT_THAT(r.out, HasSubstr("seed 5"));
  std::string gains_line;
  for (const std::string& line : lines_of(r.out)) {
    if (line.rfind("Gains:", 0) == 0) gains_line = line.substr(6);
  }
  std::istringstream in(gains_line);
  int ones = 0, count = 0;
  for (double g; in >> g; ++count) {
    EXPECT_TRUE(g == 0.0 || g == 1.0) << g;
    ones += g == 1.0;
  }
  EXPECT_EQ(count, 20);
  EXPECT_GE(ones, 8);
  // Same seed, same code.
  EXPECT_EQ(
      run_fssim("code optimize -L 20 -v 0.9 --binary --min-light 8 --restarts 3 --seed 5").out,
      r.out);
}

// ---------------------------------------------------------------------------
// sweep.

TEST_F(CodeCli, SweepPlotDrawsTheCurveAndNeedsOneRange) {
  const fs::path csv = dir_ / "sweep.csv";
  const fs::path png = dir_ / "sweep.png";
  const CommandResult r = run_fssim("sweep --input " + camera() +
                                    " --code sinc --velocity 0.5:1:0.5 --noise-free-check " +
                                    "-o " + quote(csv) + " --plot " + quote(png));
  // --noise-free-check is not an option: nothing is written.
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(png));
  const CommandResult ok =
      run_fssim("sweep --input " + camera() + " --code sinc --velocity 0.5:1:0.5 -o " + quote(csv) +
                " --plot " + quote(png));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const Image plot = read_png(png);
  EXPECT_EQ(plot.width, kPlotWidth);
  EXPECT_EQ(plot.height, kPlotHeight);
  EXPECT_THAT(ok.out, HasSubstr("Plot: "));
  const CommandResult both = run_fssim("sweep --input " + camera() +
                                       " --code sinc --velocity 0.5:1:0.5 --snr 50:100:50 -o " +
                                       quote(dir_ / "b.csv") + " --plot " + quote(dir_ / "b.png"));
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_THAT(both.err, HasSubstr("--plot"));
  EXPECT_FALSE(fs::exists(dir_ / "b.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "b.png"));
}

TEST_F(CodeCli, SweepWritesOneRowPerSetting) {
  const fs::path csv = dir_ / "sweep.csv";
  const CommandResult r = run_fssim("sweep --input " + camera() +
                                    " --code sinc --velocity 0.5:1.5:0.5 --snr 50:100:50 "
                                    "--trials 2 -o " +
                                    quote(csv));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(test::read_file(csv));
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0],
            "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,"
            "snr_level100,invertible,status");
  const char* settings[] = {"0.5,50,", "0.5,100,", "1,50,", "1,100,", "1.5,50,", "1.5,100,"};
  for (int i = 0; i < 6; ++i) {
    EXPECT_THAT(rows[i + 1], StartsWith(settings[i])) << rows[i + 1];
    EXPECT_EQ(split(rows[i + 1], ',').size(), 10u) << rows[i + 1];
  }
  // v <= 1: B = 52 and the run fits; measured within 3% of predicted.
  for (int i = 1; i <= 4; ++i) {
    const std::vector<std::string> f = split(rows[i], ',');
    EXPECT_EQ(f[2], "52");
    EXPECT_EQ(f[8], "true");
    EXPECT_EQ(f[9], "ok");
    EXPECT_NEAR(std::stod(f[3]) / std::stod(f[5]), 1.0, 0.03) << rows[i];
    EXPECT_GT(std::stod(f[4]), 0.0);
  }
  // Higher snr, lower RMSE.
  EXPECT_LT(std::stod(split(rows[2], ',')[5]), std::stod(split(rows[1], ',')[5]));
  // v = 1.5: B = 78 needs a width of 703 with the default margin: the row
  // says so, the sweep goes on and warns.
  for (int i = 5; i <= 6; ++i) {
    const std::vector<std::string> f = split(rows[i], ',');
    EXPECT_EQ(f[2], "78");
    EXPECT_EQ(f[3], "");
    EXPECT_EQ(f[9], "too-narrow");
  }
  EXPECT_THAT(r.err, HasSubstr("fssim: warning: velocity 1.5"));
  EXPECT_THAT(r.err, HasSubstr("--rmse-margin"));
  EXPECT_THAT(r.out, HasSubstr("Wrote 6 rows to"));
  EXPECT_EQ(test::list_directory(dir_.path()), std::vector<std::string>{"sweep.csv"});
}

// The sweep runs on the campaign engine with the same seeds for every
// setting (--seed, --seed + 1, ...: a run of fssim with them), and a row does
// not depend on the other settings of the grid (nor on the kernel the engine
// keeps from one snr value to the next).
TEST_F(CodeCli, SweepRowsDoNotDependOnTheGrid) {
  const auto sweep = [&](const std::string& snr, const char* name) {
    const fs::path csv = dir_ / name;
    const CommandResult r = run_fssim("sweep --input " + camera() +
                                      " --code mip --velocity 0.8 --trials 2 --seed 11 --snr " +
                                      snr + " -o " + quote(csv));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return lines_of(test::read_file(csv));
  };
  const std::vector<std::string> both = sweep("40:80:40", "both.csv");
  const std::vector<std::string> low = sweep("40", "low.csv");
  const std::vector<std::string> high = sweep("80", "high.csv");
  ASSERT_EQ(both.size(), 3u);
  ASSERT_EQ(low.size(), 2u);
  ASSERT_EQ(high.size(), 2u);
  EXPECT_EQ(both[1], low[1]);
  EXPECT_EQ(both[2], high[1]);
  EXPECT_NE(both[1], both[2]);
  const CommandResult run = run_fssim("--input " + camera() +
                                      " --code mip --velocity 0.8 --trials 2 --seed 11 --snr 80 " +
                                      "--outdir " + quote(dir_ / "run"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::read_file(dir_ / "run/report.json"));
  const std::vector<std::string> f = split(high[1], ',');
  EXPECT_EQ(std::stod(f[3]), report["trials"]["rmse_mean"].get<double>());
  EXPECT_EQ(std::stod(f[4]), report["trials"]["rmse_sd"].get<double>());
}

TEST_F(CodeCli, SweepWithAMarginAndANonInvertibleCode) {
  const fs::path csv = dir_ / "s.csv";
  const CommandResult r = run_fssim("sweep --input " + camera() +
                                    " --code accumulation --velocity 1.5 --rmse-margin 40 "
                                    "--mode analog -o " +
                                    quote(csv));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(test::read_file(csv));
  ASSERT_EQ(rows.size(), 2u);
  const std::vector<std::string> f = split(rows[1], ',');
  EXPECT_EQ(f[0], "1.5");
  EXPECT_EQ(f[2], "78");
  EXPECT_EQ(f[5], "inf");
  EXPECT_EQ(f[8], "false");
  EXPECT_EQ(f[9], "not-invertible");
  // Singular words for one trial and one row.
  EXPECT_THAT(r.out, HasSubstr("(1 trial), not invertible"));
  EXPECT_THAT(r.out, HasSubstr("Wrote 1 row to"));
}

// ---------------------------------------------------------------------------
// Usage errors: exit 2, one line naming the culprit, nothing written.

struct UsageCase {
  const char* name;
  const char* arguments;  // {input} is replaced by camera.png, {out} by a file in a temp dir
  const char* culprit;
};

void PrintTo(const UsageCase& c, std::ostream* os) { *os << c.arguments; }

class DesignUsageErrors : public ::testing::TestWithParam<UsageCase> {};

TEST_P(DesignUsageErrors, ExitTwoWithOneLine) {
  test::TempDir dir;
  std::string arguments = GetParam().arguments;
  for (const auto& [placeholder, value] :
       {std::pair<std::string, std::string>{"{input}", camera()},
        std::pair<std::string, std::string>{"{out}", quote(dir / "out.txt")}}) {
    if (const auto at = arguments.find(placeholder); at != std::string::npos) {
      arguments.replace(at, placeholder.size(), value);
    }
  }
  const CommandResult r = run_fssim(arguments);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(GetParam().culprit));
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(
    Commands, DesignUsageErrors,
    ::testing::Values(
        UsageCase{"CodeAlone", "code", "subcommand"},
        UsageCase{"UnknownCodeCommand", "code frobnicate", "frobnicate"},
        UsageCase{"SimulationOptionBeforeSubcommand", "--velocity 2 code analyze sinc",
                  "--velocity"},
        UsageCase{"GenerateUnknownFamily", "code generate raskar --length 52 -o {out}", "raskar"},
        UsageCase{"GenerateMissingLength", "code generate sinc -o {out}", "--length"},
        UsageCase{"GenerateZeroLength", "code generate sinc --length 0 -o {out}", "--length"},
        UsageCase{"GenerateHugeLength", "code generate sinc --length 100000 -o {out}", "--length"},
        UsageCase{"GenerateBandTooWide", "code generate sinc --length 52 --velocity 2 -o {out}",
                  "--velocity"},
        UsageCase{"GenerateNoMotion", "code generate mip --length 52 --velocity 0 -o {out}",
                  "--velocity"},
        UsageCase{"GenerateNanVelocity", "code generate sinc --length 52 --velocity nan",
                  "--velocity"},
        UsageCase{"AnalyzeMissingCode", "code analyze --velocity 1", "CODE"},
        UsageCase{"AnalyzeUnknownCode", "code analyze nosuchcode", "nosuchcode"},
        UsageCase{"AnalyzeAnalogWithNegativeGains", "code analyze sinc --mode analog", "analog"},
        UsageCase{"AnalyzeBadSnr", "code analyze sinc --snr 0", "--snr"},
        UsageCase{"AnalyzeBadGrid", "code analyze sinc --grid -3", "--grid"},
        UsageCase{"OptimizeMissingVelocity", "code optimize --length 52", "--velocity"},
        UsageCase{"OptimizeZeroVelocity", "code optimize --length 52 --velocity 0", "--velocity"},
        UsageCase{"OptimizeFastVelocity", "code optimize --length 52 --velocity 2.5", "--velocity"},
        UsageCase{"OptimizeLightBudgetNumerical",
                  "code optimize --length 52 --velocity 1 --min-light 5", "--min-light"},
        UsageCase{"OptimizeLightBudgetTooLarge",
                  "code optimize --length 10 --velocity 1 --binary --min-light 11", "--min-light"},
        UsageCase{"OptimizeNegativeRestarts",
                  "code optimize --length 10 --velocity 1 --restarts -1", "--restarts"},
        UsageCase{"OptimizeMode", "code optimize --length 10 --velocity 1 --mode foo", "--mode"},
        UsageCase{"AnalyzeNegativeReadNoise", "code analyze raskar --read-noise -1",
                  "--read-noise: value -1 must be finite and >= 0"},
        UsageCase{"AnalyzeNanDarkCurrent", "code analyze raskar --dark-current nan",
                  "--dark-current"},
        UsageCase{"AnalyzeAdcBits", "code analyze raskar --adc-bits 33",
                  "--adc-bits: value 33 must lie in [1, 32]"},
        UsageCase{"AnalyzeAdcGainAlone", "code analyze raskar --adc-gain 2",
                  "--adc-gain: needs --adc-bits (without an ADC there are no counts)"},
        UsageCase{"AnalyzeZeroAdcGain", "code analyze raskar --adc-bits 12 --adc-gain 0",
                  "--adc-gain: value 0"},
        UsageCase{"AnalyzeFullWell", "code analyze raskar --full-well 1000", "--full-well 1000"},
        UsageCase{"OptimizeFullWell",
                  "code optimize --length 10 --velocity 1 --full-well 1000 -o {out}",
                  "--full-well"},
        UsageCase{"OptimizeNegativeReadNoise",
                  "code optimize --length 10 --velocity 1 --read-noise -2 -o {out}",
                  "--read-noise: value -2 must be finite and >= 0"},
        UsageCase{"SweepMissingInput", "sweep --velocity 1 -o {out}", "--input"},
        UsageCase{"SweepMissingOutput", "sweep --input {input}", "--output"},
        UsageCase{"SweepZeroStep", "sweep --input {input} --velocity 0:1:0 -o {out}", "--velocity"},
        UsageCase{"SweepNanRange", "sweep --input {input} --velocity 0:nan:1 -o {out}",
                  "--velocity"},
        UsageCase{"SweepTooManyPoints", "sweep --input {input} --snr 1:20000:1 -o {out}", "--snr"},
        UsageCase{"SweepTooManySettings",
                  "sweep --input {input} --velocity 0:1:0.01 --snr 1:200:1 -o {out}", "settings"},
        UsageCase{"SweepNonPositiveSnr", "sweep --input {input} --snr -10:10:10 -o {out}", "--snr"},
        UsageCase{"SweepAnalogNegativeGains",
                  "sweep --input {input} --code sinc --mode analog -o {out}", "analog"},
        UsageCase{"SweepBadTrials", "sweep --input {input} --trials 0 -o {out}", "--trials"}),
    [](const ::testing::TestParamInfo<UsageCase>& info) { return info.param.name; });

TEST(DesignCli, SweepRuntimeErrorsExitOne) {
  test::TempDir dir;
  const CommandResult missing =
      run_fssim("sweep --input " + quote(dir / "none.png") + " -o " + quote(dir / "s.csv"));
  EXPECT_EQ(missing.exit_code, 1) << missing.err;
  expect_one_error_line(missing);
  EXPECT_THAT(missing.err, HasSubstr("none.png"));
  EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{});

  const CommandResult into_dir = run_fssim("code generate sinc -L 8 -o " + quote(dir.path()));
  EXPECT_EQ(into_dir.exit_code, 1) << into_dir.err;
  expect_one_error_line(into_dir);
}

TEST(DesignCli, HelpListsTheSubcommands) {
  const CommandResult help = run_fssim("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_THAT(help.out, HasSubstr("code"));
  EXPECT_THAT(help.out, HasSubstr("sweep"));
  const CommandResult code_help = run_fssim("code optimize --help");
  EXPECT_EQ(code_help.exit_code, 0);
  EXPECT_THAT(code_help.out, HasSubstr("--min-light"));
  EXPECT_THAT(code_help.out, HasSubstr("--binary"));
  const CommandResult sweep_help = run_fssim("sweep --help");
  EXPECT_EQ(sweep_help.exit_code, 0);
  EXPECT_THAT(sweep_help.out, HasSubstr("start:stop:step"));
}

// Every command checks --dt (and the simulator's other options) with the
// library's rules, in the simulator's words.
TEST(DesignCli, EveryCommandChecksDtAsTheSimulatorDoes) {
  const std::string rule = "--dt: value 1e-200 is out of range: it must lie in [1e-100, 1e100]";
  const struct {
    const char* arguments;
    const char* help;
  } commands[] = {
      {"--input x.png --dt 1e-200", "fssim --help"},
      {"spectra -o x.png raskar --dt 1e-200", "fssim spectra --help"},
      {"code generate sinc -L 8 --dt 1e-200", "fssim code generate --help"},
      {"code analyze raskar --dt 1e-200", "fssim code analyze --help"},
      {"code optimize -L 8 -v 1 --dt 1e-200", "fssim code optimize --help"},
      {"sweep --input x.png -o x.csv --dt 1e-200", "fssim sweep --help"},
  };
  for (const auto& c : commands) {
    const CommandResult r = run_fssim(c.arguments);
    EXPECT_EQ(r.exit_code, 2) << c.arguments;
    EXPECT_EQ(r.out, "") << c.arguments;
    EXPECT_EQ(r.err, "fssim: error: " + rule + " (see " + c.help + ")\n") << c.arguments;
  }
  const CommandResult snr = run_fssim("code analyze raskar --snr -1");
  EXPECT_EQ(snr.err, "fssim: error: --snr: value -1 must be > 0 (see fssim code analyze --help)\n");
}

TEST(DesignCli, SweepChecksEverySnrValueWithTheSimulatorsRule) {
  const CommandResult r = run_fssim("sweep --input x.png -o x.csv --snr 1e-300");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "fssim: error: --snr '1e-300': the value must lie in [1e-100, 1e100]\n");
  // The option as typed, not "snr = 1e+300"; of a range, the value that breaks the rule.
  const CommandResult big = run_fssim("sweep --input x.png -o x.csv --snr 1e300");
  EXPECT_EQ(big.err, "fssim: error: --snr '1e300': the value must lie in [1e-100, 1e100]\n");
  const CommandResult range = run_fssim("sweep --input x.png -o x.csv --snr 0:1:0.25");
  EXPECT_EQ(range.err,
            "fssim: error: --snr '0:1:0.25': every value must be > 0, the range holds 0\n");
}

// The simulator's check of a code in every command (check_code_for_mode):
// gains whose sums or |K| leave double precision are refused, not printed
// as "Sum of gains: inf".
TEST(DesignCli, EveryCommandRefusesGainsBeyondDoublePrecision) {
  test::TempDir dir;
  test::write_file(dir / "huge.txt", "1e308 1e308 1e308\n");
  test::write_file(dir / "tiny.txt", "1e-320 0 1e-320\n");
  for (const char* name : {"huge.txt", "tiny.txt"}) {
    const std::string code = quote(dir / name);
    const std::string value = name[0] == 'h' ? "1e+308" : "1e-320";
    const std::string rule = "': its largest |gain| " + value +
                             " is out of range: it must lie in [1e-100, 1e100] (scale the gains)\n";
    for (const std::string& command : {"code analyze " + code, "code analyze " + code + " --json -",
                                       "spectra -o " + quote(dir / "s.png") + " " + code}) {
      const CommandResult r = run_fssim(command);
      EXPECT_EQ(r.exit_code, 2) << command;
      EXPECT_EQ(r.out, "") << command;
      EXPECT_EQ(r.err, "fssim: error: code '" + (dir / name).string() + rule) << command;
    }
    const CommandResult sweep =
        run_fssim("sweep -i " + camera() + " -o " + quote(dir / "s.csv") + " --code " + code);
    EXPECT_EQ(sweep.exit_code, 2);
    EXPECT_EQ(sweep.err, "fssim: error: code '" + (dir / name).string() + rule);
  }
  EXPECT_FALSE(fs::exists(dir / "s.png") || fs::exists(dir / "s.csv"));
}

// A code within the rule whose analysis still leaves double precision (dt
// and the gains at the ends of their ranges) is refused as well.
TEST(DesignCli, AnalyzeRefusesFiguresBeyondDoublePrecision) {
  test::TempDir dir;
  test::write_file(dir / "small.txt", "1e-100 0 1e-100 1e-100\n");
  // |K| about 1e-200: |K|^2 underflows to 0 and M would print as infinite
  // for a code whose K has no zero.
  const CommandResult r = run_fssim("code analyze " + quote(dir / "small.txt") + " --dt 1e-100");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "fssim: error: the analysis of code '" + (dir / "small.txt").string() +
                       "' left the range of double-precision numbers: its gains (|gain| up to "
                       "1e-100), dt 1e-100 and snr 100 are too extreme together\n");
  EXPECT_EQ(run_fssim("code analyze " + quote(dir / "small.txt")).exit_code, 0);
}

// Values in messages are exact (shortest round trip), and a positional
// argument is not named as an option.
TEST(DesignCli, MessagesShowValuesExactlyAndNamesAsTyped) {
  test::TempDir dir;
  test::write_file(dir / "a.txt", "0.5 1.0000001 0\n");
  const CommandResult analog = run_fssim("code analyze " + quote(dir / "a.txt") + " --mode analog");
  EXPECT_EQ(analog.err, "fssim: error: code '" + (dir / "a.txt").string() +
                            "' cannot be used in analog mode: gain 1 is 1.0000001, analog gains "
                            "must lie in [0, 1] (use --mode numerical)\n");
  const CommandResult spectra = run_fssim("spectra -o " + quote(dir / "s.png") + " nosuchcode");
  EXPECT_EQ(spectra.exit_code, 2);
  EXPECT_THAT(spectra.err, StartsWith("fssim: error: code 'nosuchcode' is neither a built-in"));
  const CommandResult analyze = run_fssim("code analyze nosuchcode");
  EXPECT_THAT(analyze.err, StartsWith("fssim: error: code 'nosuchcode' is neither a built-in"));
  const CommandResult sweep = run_fssim("sweep -i x.png -o x.csv --code nosuchcode");
  EXPECT_THAT(sweep.err, StartsWith("fssim: error: --code 'nosuchcode' is neither a built-in"));
  const CommandResult setting = run_fssim("code analyze raskar --velocity 0.30000000000000004");
  EXPECT_THAT(setting.out, HasSubstr("velocity 0.30000000000000004, dt 1, snr 100\n"));
}

}  // namespace
}  // namespace fss
