// Numbers at the edges of what the options accept (issue 23): every number
// fssim prints or writes is finite or a documented infinity, never NaN; a
// value that is meaningless, or a run whose numbers leave double precision,
// ends in one clear line naming the option (or the settings) instead.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <regex>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "nlohmann/json.hpp"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;
using test::run_fssim;
using ::testing::HasSubstr;

// A word "nan" (printf's "nan", "-nan", "NaN"), not a part of a longer word.
bool holds_nan(const std::string& text) {
  static const std::regex kNan("(^|[^a-z])nan([^a-z]|$)", std::regex::icase);
  return std::regex_search(text, kNan);
}

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  test::write_file(path, std::string(bytes.begin(), bytes.end()));
}

class NumericExtremes : public ::testing::Test {
 protected:
  void SetUp() override {
    // 480 columns: the narrowest the default raskar code (B = 52) measures on.
    write_bytes(dir_ / "small.png", encode_png8(test::make_test_image(480, 4, 1, 7)));
  }

  // fssim on small.png with `arguments`, outputs into a fresh folder.
  CommandResult simulate(const std::string& arguments) {
    const fs::path out = dir_ / ("out" + std::to_string(runs_++));
    return run_fssim("--input " + quote(dir_ / "small.png") + " --no-plots --outdir " + quote(out) +
                     " " + arguments);
  }
  fs::path last_outdir() const { return dir_ / ("out" + std::to_string(runs_ - 1)); }

  // A run as the class wants it: exit 0, 1 or 2; no NaN on stdout, stderr or
  // in report.json; an error is the one last line of stderr; a finite
  // prediction has every figure (JSON writes NaN and infinities as null).
  void expect_no_nan(const std::string& arguments) {
    const CommandResult r = simulate(arguments);
    SCOPED_TRACE(arguments + "\nstdout:\n" + r.out + "stderr:\n" + r.err);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1 || r.exit_code == 2);
    EXPECT_FALSE(holds_nan(r.out));
    EXPECT_FALSE(holds_nan(r.err));
    if (r.exit_code != 0) {
      const std::vector<std::string> lines = test::lines_of(r.err);
      ASSERT_FALSE(lines.empty());
      EXPECT_THAT(lines.back(), ::testing::StartsWith("fssim: error: "));
      EXPECT_EQ(r.out, "");
      return;
    }
    const std::string text = test::read_file(last_outdir() / "report.json");
    EXPECT_FALSE(holds_nan(text));
    const nlohmann::json report = nlohmann::json::parse(text);
    for (const char* key : {"rmse", "rmse_ci"}) {
      EXPECT_TRUE(report["metrics"][key].is_number()) << key;
    }
    const nlohmann::json& p = report["prediction"];
    EXPECT_TRUE(p["window_mean"].is_number());
    if (p["finite"].get<bool>()) {
      for (const char* key : {"rmse", "noise", "sigma", "rmse_stationary", "snr_level100", "m"}) {
        EXPECT_TRUE(p[key].is_number()) << key;
      }
    }
  }

  test::TempDir dir_;
  int runs_ = 0;
};

// Each option with values at and beyond the ends of its range, alone or with
// the snr at its ends (`companions`, "" alone), under each noise model.
struct ExtremeCase {
  const char* option;
  std::vector<std::string> values;
  std::vector<std::string> companions;
  std::vector<std::string> noises = {"none", "poisson"};
};

void PrintTo(const ExtremeCase& c, std::ostream* os) { *os << c.option; }

class NumericExtremesOfOption : public NumericExtremes,
                                public ::testing::WithParamInterface<ExtremeCase> {};

TEST_P(NumericExtremesOfOption, PrintAndWriteNoNan) {
  const ExtremeCase& c = GetParam();
  for (const std::string& value : c.values) {
    for (const std::string& companion : c.companions) {
      for (const std::string& noise : c.noises) {
        expect_no_nan(std::string(c.option) + " " + value + " " + companion + " --noise " + noise);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Options, NumericExtremesOfOption,
    ::testing::Values(
        ExtremeCase{"--snr",
                    {"1e-100", "1e-90", "1e-78", "1e100", "1e-101"},
                    {""},
                    {"none", "poisson", "aggregated"}},
        ExtremeCase{"--velocity", {"0", "-0", "5e-324", "1e-300", "1.999", "-1e308"}, {""}},
        ExtremeCase{"--dt", {"1e-100", "1e100", "5e-324"}, {"", "--snr 1e-100"}},
        ExtremeCase{
            "--read-noise", {"5e-324", "1e100", "1e300"}, {"", "--snr 1e-100", "--snr 1e100"}},
        ExtremeCase{"--dark-current",
                    {"5e-324", "1e24", "1e30", "1e308"},
                    {"", "--snr 1e-100", "--snr 1e100"}},
        ExtremeCase{"--full-well", {"5e-324", "1", "1e308"}, {"", "--snr 1e-100", "--snr 1e100"}},
        ExtremeCase{"--adc-gain",
                    {"5e-324", "1e100", "1e308"},
                    {"--adc-bits 1", "--adc-bits 32", "--adc-bits 12 --snr 1e-100"}},
        ExtremeCase{"--adc-bits", {"1", "32"}, {"--snr 1e-100", "--snr 1e100"}},
        ExtremeCase{"--restore-velocity", {"0", "5e-324", "2", "-1e308", "1e308"}, {""}}),
    [](const ::testing::TestParamInfo<ExtremeCase>& info) {
      std::string name;
      for (const char c : std::string(info.param.option)) {
        if (c != '-') name += c;
      }
      return name;
    });

// A clean failure: the exit status and exactly this one line on stderr.
void expect_error(const CommandResult& r, int exit_code, const std::string& line) {
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  EXPECT_EQ(r.err, "fssim: error: " + line + "\n");
  EXPECT_EQ(r.out, "");
}

// At snr 1e-90 lambda2^2 = 1e-364 underflows: v_r / lambda2^2 was 0 / 0 and
// the exact prediction NaN (with "finite": true in report.json). Without
// photons worth the name the noise is V = e / lambda2 exactly, so it scales
// as 1 / snr.
TEST_F(NumericExtremes, TinySnrPredictsTheRmseThatScalesAsOneOverSnr) {
  ASSERT_EQ(simulate("--snr 1e-60").exit_code, 0);
  const nlohmann::json at60 =
      nlohmann::json::parse(test::read_file(last_outdir() / "report.json"))["prediction"];
  const CommandResult r = simulate("--snr 1e-90");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(holds_nan(r.out)) << r.out;
  const nlohmann::json at90 =
      nlohmann::json::parse(test::read_file(last_outdir() / "report.json"))["prediction"];
  ASSERT_TRUE(at90["finite"].get<bool>());
  ASSERT_TRUE(at90["noise"].is_number()) << at90;
  const double ratio = at90["noise"].get<double>() / at60["noise"].get<double>();
  EXPECT_NEAR(ratio, 1e30, 1e30 * 1e-9);
}

// G^2 / 12 overflowed and 0 * inf (the zero gains of raskar) made the SNR at
// level 100 NaN: an ADC gain is refused above 1e100 e- per count.
TEST_F(NumericExtremes, AdcGainAboveItsRangeIsRefused) {
  expect_error(simulate("--adc-bits 12 --adc-gain 1e308"), 2,
               "--adc-gain: value 1e+308 must lie in (0, 1e100]");
  EXPECT_EQ(simulate("--adc-bits 12 --adc-gain 1e100 --noise none").exit_code, 0);
}

// A float TIFF whose RMSE window has a negative mean: sigma^2 = m Q (100 /
// snr^2) M took the square root of a negative number. A negative landscape
// gives no photons: the photon noise is 0.
TEST_F(NumericExtremes, NegativeWindowMeanHasNoPhotonNoise) {
  Image negative(480, 4, 1);
  for (int y = 0; y < negative.height; ++y) {
    for (int x = 0; x < negative.width; ++x) negative.at(0, y, x) = -100.0 + (3 * x + y) % 50;
  }
  write_bytes(dir_ / "negative.tif", encode_tiff_float(negative));
  const CommandResult r = run_fssim("--input " + quote(dir_ / "negative.tif") +
                                    " --no-plots --outdir " + quote(dir_ / "neg"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(holds_nan(r.out)) << r.out;
  const nlohmann::json p =
      nlohmann::json::parse(test::read_file(dir_ / "neg" / "report.json"))["prediction"];
  EXPECT_LT(p["window_mean"].get<double>(), 0.0);
  EXPECT_EQ(p["sigma"], 0.0);
  EXPECT_EQ(p["noise"], 0.0);
  EXPECT_DOUBLE_EQ(p["rmse_stationary"].get<double>(), p["rmse_noise_free"].get<double>());
}

// --- Messages that say which option is at fault and its range ------------

TEST_F(NumericExtremes, ReadNoiseAboveItsRangeIsNamed) {
  expect_error(simulate("--read-noise 1e300"), 2,
               "--read-noise: value 1e+300 must lie in [0, 1e100]");
}

TEST_F(NumericExtremes, DarkCurrentAboveItsRangeIsNamed) {
  expect_error(simulate("--dark-current 1e308"), 2,
               "--dark-current: value 1e+308 must lie in [0, 1e100]");
}

// Above 1e24 e- a readout's dark charge swallows its own Poisson noise in
// round-off (at 1e34 the observation came out as 0, silently).
TEST_F(NumericExtremes, DarkChargeBeyondDoublePrecisionIsRefused) {
  expect_error(simulate("--dark-current 1e30"), 2,
               "dark current 1e+30 e-/slot over a readout's exposure of 1 (dt; L dt in analog "
               "mode) is a dark charge of 1e+30 e-, more than the 1e+24 e- whose Poisson noise "
               "double precision can resolve: lower the dark current or dt");
  EXPECT_EQ(simulate("--dark-current 1e24 --noise none").exit_code, 0);
}

// Within their ranges, together: the message lists the settings, the sensor
// among them (it blamed "the gains, dt or snr").
TEST_F(NumericExtremes, SimulationBeyondDoublePrecisionNamesTheSensor) {
  expect_error(simulate("--read-noise 1e100 --snr 1e-100"), 2,
               "the simulation left the range of double-precision numbers (RMSE inf): the gains "
               "of code 'raskar' (|gain| from 1 to 1), dt 1, snr 1e-100 and read noise 1e+100 e- "
               "are too extreme together");
}

TEST_F(NumericExtremes, RestoreVelocityIsNamedAsSuch) {
  expect_error(simulate("--restore-velocity 1e308"), 2,
               "the blur of restore velocity 1e+308 over 52 slots of dt 1 "
               "spans inf pixels, more than the image width 480");
  expect_error(simulate("--velocity -1e308"), 2,
               "the blur of velocity -1e+308 over 52 slots of dt 1 spans inf pixels, more than "
               "the image width 480");
}

// It said "NoiseFigure: readout_slots inf must be finite".
TEST_F(NumericExtremes, OptimizerSaysWhichSensorOptionsAreTooNoisy) {
  expect_error(run_fssim("code optimize -L 4 -v 1 --read-noise 1e100 --snr 1e-100"), 2,
               "--snr 1e-100 with the sensor's read noise 1e+100 e- RMS per readout: its readout "
               "noise is more than 1e308 slots of level-100 light, beyond double precision; lower "
               "--read-noise, --dark-current or --adc-gain, or raise --snr");
}

TEST_F(NumericExtremes, AnalysisBeyondDoublePrecisionNamesTheSensor) {
  expect_error(run_fssim("code analyze raskar --read-noise 1e100 --snr 1e-100"), 2,
               "the analysis of code 'raskar' left the range of double-precision numbers: its "
               "gains (|gain| up to 1), dt 1, snr 1e-100 and the sensor (read noise 1e+100 e- "
               "RMS per readout) are too extreme together");
}

// The optimizer's report had "Cauchy-Schwarz bound inf" near v = 0.
TEST_F(NumericExtremes, OptimizerReportHasNoInfiniteBound) {
  const CommandResult r = run_fssim("code optimize -L 4 -v 1e-300 --restarts 1 --iterations 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("no finite Cauchy-Schwarz bound at |v| dt = 1e-300)"));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("inf")));
  EXPECT_FALSE(holds_nan(r.out));
}

// A code name with a NUL (from a campaign file) was cut at the NUL; the file
// system would have read the path up to it.
TEST_F(NumericExtremes, CodeNameWithANulIsEscaped) {
  test::write_file(dir_ / "c.json",
                   "{\"input\": " + nlohmann::json((dir_ / "small.png").string()).dump() +
                       ", \"code\": [\"rask\\u0000ar\"], \"trials\": 1}");
  expect_error(run_fssim("campaign -f " + quote(dir_ / "c.json") + " -o " + quote(dir_ / "c")), 2,
               "code 'rask\\x00ar' holds a NUL byte: no built-in code or file name has one");
}

}  // namespace
}  // namespace fss
