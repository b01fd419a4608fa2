// End-to-end tests of the fssim binary: the reference regression, output
// files, reproducibility, exit codes and error messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <ostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/outputs.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_fssim;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

const char kFixture[] = "camera_numerical_raskar_v1_noisefree";

using test::quote;

std::string camera() { return quote(test::source_path("data/camera.png")); }

using test::lines_of;

std::vector<std::string> sorted_output_names() {
  std::vector<std::string> names = output_file_names();
  std::sort(names.begin(), names.end());
  return names;
}

// The lines of stdout but the "Outputs: <dir>" one, which names the outdir.
std::vector<std::string> report_lines(const std::string& out) {
  std::vector<std::string> lines;
  for (const std::string& line : lines_of(out)) {
    if (line.rfind("Outputs:", 0) != 0) lines.push_back(line);
  }
  return lines;
}

// Writes `image` as an 8-bit PNG at `path`.
void write_png(const fs::path& path, const Image& image) {
  const std::vector<std::uint8_t> bytes = encode_png8(image);
  test::write_file(path, std::string(bytes.begin(), bytes.end()));
}

// The value of "label: value" on line `index` of stdout.
double metric_line(const std::string& out, std::size_t index, const std::string& label) {
  const std::vector<std::string> lines = lines_of(out);
  if (index >= lines.size()) {
    ADD_FAILURE() << "stdout has no line " << index << ":\n" << out;
    return std::nan("");
  }
  const std::regex pattern("^" + label + ": (-?[0-9]+\\.[0-9]+)$");
  std::smatch match;
  if (!std::regex_match(lines[index], match, pattern)) {
    ADD_FAILURE() << "line " << index << " is '" << lines[index] << "', expected '" << label
                  << ": <number>'";
    return std::nan("");
  }
  return std::stod(match[1].str());
}

// Exactly one line on stderr, as the error contract says.
void expect_one_error_line(const CommandResult& result) {
  const std::vector<std::string> lines = lines_of(result.err);
  EXPECT_EQ(lines.size(), 1u) << "stderr:\n" << result.err;
  EXPECT_TRUE(!result.err.empty() && result.err.back() == '\n') << result.err;
  if (!lines.empty()) EXPECT_THAT(lines[0], StartsWith("fssim: error:"));
}

// The outdir holds no file: it is absent or empty.
void expect_no_outputs(const fs::path& outdir) {
  if (fs::exists(outdir)) {
    EXPECT_TRUE(fs::is_directory(outdir)) << outdir;
    EXPECT_EQ(test::list_directory(outdir), std::vector<std::string>{}) << outdir;
  }
}

// Every file of two output directories is byte-identical.
void expect_identical_directories(const fs::path& a, const fs::path& b) {
  const std::vector<std::string> names = test::list_directory(a);
  EXPECT_EQ(names, sorted_output_names());
  EXPECT_EQ(names, test::list_directory(b));
  for (const std::string& name : names) {
    EXPECT_TRUE(test::read_file(a / name) == test::read_file(b / name)) << name << " differs";
  }
}

// ---------------------------------------------------------------------------
// (a) The reference regression: camera.png, raskar, numerical, v = 1, noise-free.

class CliReference : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    result_ = new CommandResult(
        run_fssim("--input " + camera() +
                  " --code raskar --mode numerical --velocity 1 --noise none --outdir " +
                  quote(dir_->path() / "out")));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete dir_;
    result_ = nullptr;
    dir_ = nullptr;
  }
  static fs::path out(const std::string& name) { return dir_->path() / "out" / name; }

  // Our 8-bit image is within one gray level of the fixture's at every pixel.
  static void expect_matches_fixture(const std::string& name) {
    const Image ours = read_png(out(name));
    const Image reference = read_png(test::fixture_path(std::string(kFixture) + "/" + name));
    ASSERT_EQ(ours.width, 356) << name;
    ASSERT_EQ(ours.height, 512) << name;
    ASSERT_EQ(ours.channels, 1) << name;
    ASSERT_EQ(reference.width, 356) << name;
    ASSERT_EQ(reference.height, 512) << name;
    // docs/method.md §8: the same images to within 1 gray level everywhere.
    EXPECT_LE(test::max_abs_difference(ours, reference), 1.0) << name;
  }

  static test::TempDir* dir_;
  static CommandResult* result_;
};
test::TempDir* CliReference::dir_ = nullptr;
CommandResult* CliReference::result_ = nullptr;

TEST_F(CliReference, Succeeds) {
  EXPECT_EQ(result_->exit_code, 0) << result_->err;
  EXPECT_EQ(result_->err, "");
  EXPECT_EQ(test::list_directory(dir_->path() / "out"), sorted_output_names());
}

TEST_F(CliReference, ObservedMatchesTheReference) { expect_matches_fixture("observed.png"); }
TEST_F(CliReference, RestoredMatchesTheReference) { expect_matches_fixture("restored.png"); }
TEST_F(CliReference, GroundTruthMatchesTheReference) { expect_matches_fixture("groundtruth.png"); }

TEST_F(CliReference, ResidualHasTheOutputSize) {
  const Image residual = read_png(out("residual.png"));
  EXPECT_EQ(residual.width, 356);
  EXPECT_EQ(residual.height, 512);
  EXPECT_EQ(residual.channels, 1);
}

TEST_F(CliReference, PrintsTheFourMetricsFirst) {
  const std::string& o = result_->out;
  // The tolerance of docs/method.md §8 on the RMSE; PSNR = 20 log10(255 / RMSE) moves by
  // 8.69 dRMSE / RMSE, i.e. 0.021 dB (RMSE) and 0.0087 dB (RMSE_CI).
  EXPECT_NEAR(metric_line(o, 0, "RMSE"), 0.417289, 1e-3);
  EXPECT_NEAR(metric_line(o, 1, "PSNR"), 55.722061, 0.025);
  EXPECT_NEAR(metric_line(o, 2, "Contrast Invariant RMSE"), 1.005121, 1e-3);
  EXPECT_NEAR(metric_line(o, 3, "Contrast Invariant PSNR"), 48.086433, 0.01);
}

TEST_F(CliReference, PrintsThePredictionAndTheSeed) {
  const std::vector<std::string> lines = lines_of(result_->out);
  ASSERT_GE(lines.size(), 8u) << result_->out;
  EXPECT_THAT(lines[4], StartsWith("SSIM: "));  // after the reference program's four
  EXPECT_THAT(lines[5], StartsWith("Predicted RMSE: "));
  EXPECT_THAT(lines[6], StartsWith("Stationary approximation: RMSE "));
  EXPECT_THAT(result_->out, HasSubstr("\nSeed: 0\n"));
}

TEST_F(CliReference, CodeTxtIsTheReferenceFile) {
  EXPECT_EQ(test::read_file(out("code.txt")),
            test::read_file(test::fixture_path(std::string(kFixture) + "/code.txt")));
}

// (h) A code file in the reference format gives the same result as --code raskar.
TEST_F(CliReference, ReferenceCodeFileGivesTheSameRmse) {
  test::TempDir dir;
  fs::copy_file(test::fixture_path(std::string(kFixture) + "/code.txt"), dir / "code.txt");
  const CommandResult r =
      run_fssim("--input " + camera() + " --code " + quote(dir / "code.txt") +
                " --mode numerical --velocity 1 --noise none --outdir " + quote(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> ours = lines_of(r.out);
  const std::vector<std::string> builtin = lines_of(result_->out);
  ASSERT_FALSE(ours.empty());
  ASSERT_FALSE(builtin.empty());
  EXPECT_EQ(ours[0], builtin[0]);
  EXPECT_THAT(ours[0], StartsWith("RMSE: "));
}

// ---------------------------------------------------------------------------
// (b), (c) Reproducibility.

class CliRuns : public ::testing::Test {
 protected:
  // A small gray input that satisfies W > 9B for L = 52.
  fs::path small_input(const std::string& name = "input.png", int width = 480, int height = 48) {
    const fs::path path = dir_ / name;
    write_png(path, test::make_test_image(width, height, 1, 3));
    return path;
  }
  test::TempDir dir_;
};

TEST_F(CliRuns, SameSeedGivesIdenticalFilesAndAnotherSeedDoesNot) {
  const fs::path input = small_input();
  auto run = [&](const std::string& seed, const std::string& outdir) {
    const CommandResult r = run_fssim("--input " + quote(input) + " --seed " + seed +
                                      " --noise poisson --outdir " + quote(dir_ / outdir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r;
  };
  const CommandResult a = run("42", "a");
  const CommandResult b = run("42", "b");
  const CommandResult c = run("43", "c");
  expect_identical_directories(dir_ / "a", dir_ / "b");
  EXPECT_EQ(report_lines(a.out), report_lines(b.out));
  EXPECT_THAT(a.out, StartsWith("RMSE: "));
  EXPECT_THAT(a.out, HasSubstr("\nSeed: 42\n"));
  EXPECT_FALSE(test::read_file(dir_ / "a/observed.png") ==
               test::read_file(dir_ / "c/observed.png"));
}

TEST_F(CliRuns, ThreadCountGivesIdenticalFiles) {
  auto run = [&](const std::string& threads) {
    const CommandResult r = run_fssim("--input " + camera() + " --seed 7 --threads " + threads +
                                      " --outdir " + quote(dir_ / ("t" + threads)));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r;
  };
  const CommandResult one = run("1");
  const CommandResult two = run("2");
  expect_identical_directories(dir_ / "t1", dir_ / "t2");
  EXPECT_EQ(report_lines(one.out), report_lines(two.out));
  EXPECT_THAT(one.out, StartsWith("RMSE: "));
}

TEST_F(CliRuns, OneAndFourThreadsGiveIdenticalFilesOnEveryPath) {
  // RGB, a non-integer velocity (one transform per slot rather than shifts),
  // both modes and two trials: every path of the pipeline split over threads.
  const fs::path input = dir_ / "rgb.png";
  write_png(input, test::make_test_image(500, 37, 3, 8));
  for (const std::string mode : {"numerical", "analog"}) {
    const std::string code = mode == "analog" ? "raskar" : "mip";
    auto run = [&](const std::string& threads) {
      const fs::path outdir = dir_ / (mode + threads);
      const CommandResult r = run_fssim("--input " + quote(input) + " --code " + code + " --mode " +
                                        mode + " --velocity 0.7 --trials 2 --seed 11 --threads " +
                                        threads + " --outdir " + quote(outdir));
      EXPECT_EQ(r.exit_code, 0) << r.err;
      return r;
    };
    const CommandResult one = run("1");
    const CommandResult four = run("4");
    expect_identical_directories(dir_ / (mode + "1"), dir_ / (mode + "4"));
    EXPECT_EQ(report_lines(one.out), report_lines(four.out)) << mode;
  }
}

TEST_F(CliRuns, RestoreVelocityEqualToTheTrueOneIsANormalRun) {
  const fs::path input = small_input();
  const CommandResult normal = run_fssim("--input " + quote(input) + " --velocity 0.9 --seed 4" +
                                         " --outdir " + quote(dir_ / "normal"));
  const CommandResult same =
      run_fssim("--input " + quote(input) + " --velocity 0.9 --restore-velocity 0.9 --seed 4" +
                " --outdir " + quote(dir_ / "same"));
  ASSERT_EQ(normal.exit_code, 0) << normal.err;
  ASSERT_EQ(same.exit_code, 0) << same.err;
  for (const char* name : {"observed.png", "restored.png", "groundtruth.png", "residual.png"}) {
    EXPECT_EQ(test::read_file(dir_ / "normal" / name), test::read_file(dir_ / "same" / name))
        << name;
  }
  EXPECT_EQ(lines_of(normal.out)[0], lines_of(same.out)[0]);
  EXPECT_THAT(same.out, HasSubstr("Restore velocity: 0.9 (true velocity 0.9)"));
  const CommandResult wrong =
      run_fssim("--input " + quote(input) + " --velocity 0.9 --restore-velocity 1 --seed 4" +
                " --outdir " + quote(dir_ / "wrong"));
  ASSERT_EQ(wrong.exit_code, 0) << wrong.err;
  EXPECT_NE(lines_of(normal.out)[0], lines_of(wrong.out)[0]);
}

TEST_F(CliRuns, MemoryLimitRefusesBeforeWritingAnything) {
  const fs::path outdir = dir_ / "out";
  const CommandResult small =
      run_fssim("--input " + camera() + " --max-memory 1M --outdir " + quote(outdir));
  EXPECT_EQ(small.exit_code, 1);
  const std::vector<std::string> lines = lines_of(small.err);
  ASSERT_EQ(lines.size(), 1u) << small.err;
  EXPECT_THAT(lines[0], StartsWith("fssim: error: "));
  EXPECT_THAT(lines[0], HasSubstr("--max-memory"));
  EXPECT_THAT(lines[0], HasSubstr("1.0 MiB"));
  EXPECT_FALSE(fs::exists(outdir));
  // Enough to decode camera.png (2.3 MiB) but not to run on it (about 16 MiB).
  const CommandResult decode_only =
      run_fssim("--input " + camera() + " --max-memory 4M --outdir " + quote(outdir));
  EXPECT_EQ(decode_only.exit_code, 1);
  EXPECT_THAT(decode_only.err, HasSubstr("needs about"));
  EXPECT_FALSE(fs::exists(outdir));
  const CommandResult unlimited =
      run_fssim("--input " + camera() + " --max-memory 0 --noise none --outdir " + quote(outdir));
  EXPECT_EQ(unlimited.exit_code, 0) << unlimited.err;
  const CommandResult bad =
      run_fssim("--input " + camera() + " --max-memory 12X --outdir " + quote(outdir));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("--max-memory"));
}

// ---------------------------------------------------------------------------
// (d), (e) Usage errors: exit 2, one line on stderr, no outputs.

TEST_F(CliRuns, AnalogModeRefusesTheSincCode) {
  const CommandResult r = run_fssim("--input " + camera() + " --mode analog --code sinc --outdir " +
                                    quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr("sinc"));
  EXPECT_EQ(r.out, "");
  expect_no_outputs(dir_ / "out");
}

struct UsageCase {
  const char* name;
  const char* arguments;  // put before --outdir; {input} is replaced by camera.png
  const char* culprit;    // the option or value the message must name
};

void PrintTo(const UsageCase& c, std::ostream* os) { *os << c.arguments; }

class CliUsageErrors : public ::testing::TestWithParam<UsageCase> {
 protected:
  static std::string arguments() {
    std::string text = GetParam().arguments;
    const std::string placeholder = "{input}";
    if (const auto at = text.find(placeholder); at != std::string::npos) {
      text.replace(at, placeholder.size(), camera());
    }
    return text;
  }
};

TEST_P(CliUsageErrors, ExitTwoWithOneLine) {
  test::TempDir dir;
  const CommandResult r = run_fssim(arguments() + " --outdir " + quote(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(GetParam().culprit));
  expect_no_outputs(dir / "out");
}

TEST_P(CliUsageErrors, MessageIsShortAndReadable) {
  test::TempDir dir;
  const CommandResult r = run_fssim(arguments() + " --outdir " + quote(dir / "out"));
  // error.h: a one-line, self-contained message saying what was expected;
  // 200 characters is ample for that (no 309-digit DBL_MAX bound).
  EXPECT_LE(r.err.size(), 200u) << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    Options, CliUsageErrors,
    ::testing::Values(
        UsageCase{"UnknownOption", "--input {input} --frobnicate 3", "frobnicate"},
        UsageCase{"MissingInput", "--code raskar", "--input"},
        UsageCase{"VelocityNotANumber", "--input {input} --velocity abc", "--velocity"},
        UsageCase{"VelocityNan", "--input {input} --velocity nan", "--velocity"},
        UsageCase{"VelocityInf", "--input {input} --velocity inf", "--velocity"},
        UsageCase{"SnrZero", "--input {input} --snr 0", "--snr"},
        UsageCase{"SnrNegative", "--input {input} --snr -1", "--snr"},
        UsageCase{"DtZero", "--input {input} --dt 0", "--dt"},
        UsageCase{"ModeUnknown", "--input {input} --mode foo", "--mode"},
        UsageCase{"NoiseUnknown", "--input {input} --noise foo", "--noise"},
        UsageCase{"TrialsZero", "--input {input} --trials 0", "--trials"},
        UsageCase{"ThreadsNegative", "--input {input} --threads -1", "--threads"},
        UsageCase{"RestoreVelocityNan", "--input {input} --restore-velocity nan",
                  "--restore-velocity"},
        UsageCase{"MarginNegative", "--input {input} --rmse-margin -1", "--rmse-margin"},
        UsageCase{"UnknownCodeName", "--input {input} --code nosuchcode", "nosuchcode"},
        // the sensor (docs/method.md §10), by the library's rules
        UsageCase{"ReadNoiseNegative", "--input {input} --read-noise -1",
                  "--read-noise: value -1 must be finite and >= 0"},
        UsageCase{"ReadNoiseNan", "--input {input} --read-noise nan", "--read-noise"},
        UsageCase{"DarkCurrentNegative", "--input {input} --dark-current -0.5",
                  "--dark-current: value -0.5 must be finite and >= 0"},
        UsageCase{"FullWellZero", "--input {input} --full-well 0",
                  "--full-well: value 0 must be finite and > 0"},
        UsageCase{"AdcBitsTooMany", "--input {input} --adc-bits 33",
                  "--adc-bits: value 33 must lie in [1, 32]"},
        UsageCase{"AdcBitsNotAnInteger", "--input {input} --adc-bits 1.5", "--adc-bits"},
        UsageCase{"AdcGainWithoutBits", "--input {input} --adc-gain 2",
                  "--adc-gain: needs --adc-bits"},
        UsageCase{"AdcGainZero", "--input {input} --adc-bits 8 --adc-gain 0",
                  "--adc-gain: value 0 must be finite and > 0"},
        UsageCase{"AggregatedWithFullWell", "--input {input} --noise aggregated --full-well 1e5",
                  "--noise: value aggregated must be poisson or none with a full well or an ADC"},
        UsageCase{"AggregatedWithAdc", "--input {input} --noise aggregated --adc-bits 12",
                  "--noise: value aggregated must be poisson or none with a full well or an ADC"}),
    [](const ::testing::TestParamInfo<UsageCase>& info) { return info.param.name; });

// ---------------------------------------------------------------------------
// The sensor (docs/method.md §10): stdout, report.json and report.html say
// what it was; a default run says nothing of it.

TEST_F(CliRuns, SensorIsReportedOnlyWhenEnabled) {
  const fs::path input = small_input();
  const CommandResult plain =
      run_fssim("--input " + quote(input) + " --outdir " + quote(dir_ / "plain"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_THAT(plain.out, Not(HasSubstr("Sensor")));
  const std::string plain_json = test::read_file(dir_ / "plain" / "report.json");
  EXPECT_THAT(plain_json, Not(HasSubstr("sensor")));
  EXPECT_THAT(plain_json, Not(HasSubstr("\"exact\"")));

  const CommandResult sensor = run_fssim("--input " + quote(input) +
                                         " --read-noise 4 --dark-current 0.5 --adc-bits 14 "
                                         "--adc-gain 3 --report --outdir " +
                                         quote(dir_ / "sensor"));
  ASSERT_EQ(sensor.exit_code, 0) << sensor.err;
  EXPECT_THAT(sensor.out, HasSubstr("Sensor: read noise 4 e-, dark current 0.5 e-/slot, full well "
                                    "none, ADC 14 bits, gain 3 e-/count\n"));
  const std::string json = test::read_file(dir_ / "sensor" / "report.json");
  EXPECT_THAT(json, HasSubstr("\"sensor\": {"));
  EXPECT_THAT(json, HasSubstr("\"read_noise_electrons\": 4.0"));
  EXPECT_THAT(json, HasSubstr("\"adc_bits\": 14"));
  EXPECT_THAT(json, HasSubstr("\"full_well_electrons\": null"));
  EXPECT_THAT(json, HasSubstr("\"exact\": true"));
  EXPECT_THAT(test::read_file(dir_ / "sensor" / "report.html"), HasSubstr("read noise 4 e⁻"));
  // the read noise adds to the predicted error
  EXPECT_NE(plain.out, sensor.out);
}

TEST_F(CliRuns, SaturatingFullWellWarnsAndMarksThePredictionApproximate) {
  const CommandResult r = run_fssim("--input " + quote(small_input()) +
                                    " --full-well 12000 --report --outdir " + quote(dir_ / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("readouts saturate"));
  EXPECT_THAT(r.out, HasSubstr(", approximate: the sensor clips readouts\n"));
  const std::string json = test::read_file(dir_ / "out" / "report.json");
  EXPECT_THAT(json, HasSubstr("\"exact\": false"));
  EXPECT_THAT(json, HasSubstr("\"full_well_electrons\": 12000.0"));
  EXPECT_THAT(test::read_file(dir_ / "out" / "report.html"),
              HasSubstr("predicted RMSE (approximate: the sensor clips readouts)"));
}

// ---------------------------------------------------------------------------
// (f) Runtime errors: exit 1, one line naming the file, no outputs.

TEST_F(CliRuns, MissingInputFile) {
  const fs::path input = dir_ / "no-such-image.png";
  const CommandResult r = run_fssim("--input " + quote(input) + " --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(input.string()));
  expect_no_outputs(dir_ / "out");
}

TEST_F(CliRuns, InputThatIsNotAPng) {
  const fs::path input = dir_ / "notes.png";
  test::write_file(input, "just some text, not an image\n");
  const CommandResult r = run_fssim("--input " + quote(input) + " --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(input.string()));
  expect_no_outputs(dir_ / "out");
}

TEST_F(CliRuns, EmptyCodeFile) {
  const fs::path code = dir_ / "empty-code.txt";
  test::write_file(code, "");
  const CommandResult r = run_fssim("--input " + camera() + " --code " + quote(code) +
                                    " --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(code.string()));
  expect_no_outputs(dir_ / "out");
}

TEST_F(CliRuns, CodeFileWithANonNumericToken) {
  const fs::path code = dir_ / "bad-code.txt";
  test::write_file(code, "1;\n0;\n1;\nabc;\n1;\n");
  const CommandResult r = run_fssim("--input " + camera() + " --code " + quote(code) +
                                    " --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(code.string()));
  EXPECT_THAT(r.err, HasSubstr("abc"));
  expect_no_outputs(dir_ / "out");
}

// ---------------------------------------------------------------------------
// (g) Help and version.

TEST(Cli, HelpAndVersionExitZero) {
  const CommandResult help = run_fssim("--help");
  EXPECT_EQ(help.exit_code, 0) << help.err;
  EXPECT_THAT(help.out, HasSubstr("--input"));
  EXPECT_THAT(help.out, HasSubstr("--rmse-margin"));
  const CommandResult version = run_fssim("--version");
  EXPECT_EQ(version.exit_code, 0) << version.err;
  EXPECT_THAT(version.out, StartsWith("fssim "));
}

// ---------------------------------------------------------------------------
// (i) Narrow images.

TEST_F(CliRuns, TooNarrowImageExplainsTheMargin) {
  const fs::path input = small_input("narrow.png", 400, 64);
  const CommandResult r = run_fssim("--input " + quote(input) + " --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 2);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr("--rmse-margin"));
  EXPECT_THAT(r.err, HasSubstr("469"));  // 9B + 1 with B = 52
  expect_no_outputs(dir_ / "out");

  const CommandResult with_margin =
      run_fssim("--input " + quote(input) + " --rmse-margin 10 --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(with_margin.exit_code, 0) << with_margin.err;
  EXPECT_THAT(with_margin.out, HasSubstr("RMSE columns [10, 234)"));  // Wo = 400 - 156
}

// ---------------------------------------------------------------------------
// (j) Output directory problems.

TEST_F(CliRuns, OutdirThatIsAFileIsRefused) {
  const fs::path input = small_input();
  const fs::path file = dir_ / "taken";
  test::write_file(file, "do not touch\n");
  const CommandResult r = run_fssim("--input " + quote(input) + " --outdir " + quote(file));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(file.string()));
  EXPECT_EQ(test::read_file(file), "do not touch\n");
  EXPECT_EQ(test::list_directory(dir_.path()), (std::vector<std::string>{"input.png", "taken"}));
}

TEST_F(CliRuns, RefusesToOverwriteTheInput) {
  const fs::path input = small_input("observed.png");
  const std::string before = test::read_file(input);
  const CommandResult r = run_fssim("--input " + quote(input) + " --outdir " + quote(dir_.path()));
  EXPECT_EQ(r.exit_code, 1);
  expect_one_error_line(r);
  EXPECT_THAT(r.err, HasSubstr(input.string()));
  EXPECT_TRUE(test::read_file(input) == before);
  EXPECT_EQ(test::list_directory(dir_.path()), std::vector<std::string>{"observed.png"});
}

// ---------------------------------------------------------------------------
// (k) A code that is not invertible.

TEST_F(CliRuns, AccumulationWarnsAndPredictsNothing) {
  const fs::path input = small_input();
  const CommandResult r =
      run_fssim("--input " + quote(input) + " --code accumulation --noise none --outdir " +
                quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  bool warned = false;
  for (const std::string& line : lines_of(r.err)) {
    warned = warned || (line.rfind("fssim: warning:", 0) == 0 &&
                        line.find("not invertible") != std::string::npos);
  }
  EXPECT_TRUE(warned) << "stderr:\n" << r.err;
  bool none = false;
  for (const std::string& line : lines_of(r.out)) {
    none = none || line.rfind("Predicted RMSE: none", 0) == 0;
  }
  EXPECT_TRUE(none) << "stdout:\n" << r.out;
  EXPECT_EQ(test::list_directory(dir_ / "out"), sorted_output_names());
}

// ---------------------------------------------------------------------------
// (l) Pictures: plots, sheet, report page, and the spectra subcommand.

TEST_F(CliRuns, NoPlotsLeavesThePlotsOut) {
  const fs::path input = small_input();
  const CommandResult r =
      run_fssim("--input " + quote(input) + " --no-plots --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> expected = output_file_names({false, false, false});
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(test::list_directory(dir_ / "out"), expected);
}

// A run that draws no plot and reads or writes no TIFF never loads PLplot or
// libtiff, nor their dependencies. (With plots, the loader's trace would reach
// stderr while a picture is drawn, which fails the picture by design.)
TEST_F(CliRuns, PlotAndTiffLibrariesLoadOnlyWhenUsed) {
  const fs::path input = small_input();
  const std::string run = "LD_DEBUG=files '" + std::string(FSSIM_BINARY_PATH) + "' --input " +
                          quote(input) + " --outdir " + quote(dir_ / "out");
  const CommandResult bare = test::run_command(run + " --no-plots");
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  ASSERT_THAT(bare.err, HasSubstr("file=libpng"));  // the loader's trace is there
  EXPECT_THAT(bare.err, Not(HasSubstr("libplplot")));
  EXPECT_THAT(bare.err, Not(HasSubstr("libtiff")));
}

TEST_F(CliRuns, ReportAndSheetAreWrittenWithTheOtherOutputs) {
  const fs::path input = small_input();
  const CommandResult r =
      run_fssim("--input " + quote(input) + " --report --sheet --outdir " + quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_THAT(r.out, StartsWith("RMSE: "));
  std::vector<std::string> expected = output_file_names({true, true, true});
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(test::list_directory(dir_ / "out"), expected);
  const std::string page = test::read_file(dir_ / "out/report.html");
  for (const std::string& name : expected) {
    EXPECT_THAT(page, HasSubstr("href=\"" + name + "\"")) << name;
  }
  const Image sheet = read_png(dir_ / "out/sheet.png");
  const Image observed = read_png(dir_ / "out/observed.png");
  // header 52, margin 8, the residual's scale 58 (fss/io/plot.h)
  EXPECT_EQ(sheet.height, observed.height + kSheetHeaderHeight + kSheetMargin + kSheetScaleHeight);
  EXPECT_EQ(sheet.width, 3 * observed.width + 32);
}

TEST(CliSpectra, WritesTheOverlayPlot) {
  test::TempDir dir;
  const CommandResult r =
      run_fssim("spectra --output " + quote(dir / "overlay.png") + " snapshot raskar mip");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::vector<std::string> lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 4u) << r.out;
  EXPECT_THAT(lines[0], StartsWith("snapshot: min |K| "));
  EXPECT_THAT(lines[1], StartsWith("raskar: min |K| "));
  EXPECT_EQ(lines[3], "Plot: " + (dir / "overlay.png").string());
  const Image plot = read_png(dir / "overlay.png");
  EXPECT_EQ(plot.width, 800);
  EXPECT_EQ(plot.height, 420);
  EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{"overlay.png"});

  const CommandResult sized = run_fssim(
      "spectra --linear --width 500 --height 300 --velocity 0.5 "
      "--output " +
      quote(dir / "small.png") + " accumulation");
  ASSERT_EQ(sized.exit_code, 0) << sized.err;
  EXPECT_THAT(sized.out, HasSubstr("(not invertible)"));
  EXPECT_EQ(read_png(dir / "small.png").width, 500);
}

TEST(CliSpectra, UsageErrors) {
  test::TempDir dir;
  const std::string output = " --output " + quote(dir / "x.png");
  for (const std::string& arguments : std::vector<std::string>{
           "spectra" + output, "spectra raskar", "spectra --width 10" + output + " raskar",
           "spectra --dt 0" + output + " raskar", "spectra" + output + " nosuchcode"}) {
    const CommandResult r = run_fssim(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.err;
    expect_one_error_line(r);
    EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{}) << arguments;
  }
  const CommandResult nine = run_fssim("spectra" + output +
                                       " raskar raskar raskar raskar raskar raskar raskar raskar "
                                       "raskar");
  EXPECT_EQ(nine.exit_code, 2);
  EXPECT_THAT(nine.err, HasSubstr("1 to 8 codes"));
}

}  // namespace
}  // namespace fss
