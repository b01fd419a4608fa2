// Tests of the output files of a run (outputs.h): spectrum.txt, report.json,
// the optional plots, sheet and page, the observed rows collected as 8-bit
// samples, and the all-or-nothing writing of the output directory.
#include "fss/io/outputs.h"
#include "io/observed_png8.h"
#include "io/run_plots.h"
#include "io/write_run.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"
#include "io/html_report.h"
#include "io/output_set.h"
#include "io/report_json_value.h"
#include "io/run_text.h"
#include "io/sheet.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::string> sorted(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return names;
}

// The input of the small real run below.
const Image& small_input() {
  static const Image image = test::make_test_image(64, 8, 1, 5);
  return image;
}

// A small real run: 64 x 8 gray, a 4-slot code, so B = 4 and Wo = 52.
SimulationReport small_report(const std::vector<double>& gains = {1.0, 0.0, 1.0, 1.0},
                              std::uint64_t seed = 3) {
  SimulationOptions options;
  options.seed = seed;
  options.threads = 1;
  return Simulate(options, small_input(), ShutterCode{"short", gains});
}

std::string as_string(const std::vector<std::uint8_t>& bytes) {
  return {bytes.begin(), bytes.end()};
}

std::string png_bytes(const Image& image) { return as_string(encode_png8(image)); }

// The expected content of each output file of `report`.
std::vector<std::pair<std::string, std::string>> expected_files(const SimulationReport& report,
                                                                const std::string& input_path) {
  return {
      {"observed.png", png_bytes(report.observed)},
      {"restored.png", png_bytes(report.restored)},
      {"groundtruth.png", png_bytes(groundtruth_image(small_input(), report))},
      {"residual.png", png_bytes(residual_image(small_input(), report))},
      {"code.txt", format_code_txt({report.code_name, report.gains})},
      {"spectrum.txt",
       format_spectrum_txt(report.gains, report.options.velocity_px_per_slot, report.options.dt)},
      {"code.png", as_string(plot_code_png(report.gains, report.code_name))},
      {"spectrum.png", as_string(plot_spectrum_png(report.gains, report.code_name,
                                                   report.options.velocity_px_per_slot,
                                                   report.options.dt, report.kernel))},
  };
}

// ---------------------------------------------------------------------------
// spectrum.txt

TEST(FormatSpectrumTxt, HundredSamplesOfAbsK) {
  const std::vector<double> gains = builtin_code("random").value().gains;
  const double v = 0.8, dt = 1.2;
  const std::vector<std::string> lines = test::lines_of(format_spectrum_txt(gains, v, dt));
  ASSERT_EQ(lines.size(), 100u);
  EXPECT_EQ(lines[0].substr(0, 9), "-3.14159 ");
  for (int j = 0; j < 100; ++j) {
    std::istringstream in(lines[j]);
    double xi = 0.0, magnitude = 0.0;
    ASSERT_TRUE(in >> xi >> magnitude) << lines[j];
    std::string rest;
    EXPECT_FALSE(in >> rest) << "extra text on line " << j << ": " << lines[j];
    const double expected_xi = -M_PI + j * 2.0 * M_PI / 100.0;
    const double expected = std::abs(transfer_function(gains, v, dt, expected_xi));
    // Six significant digits are printed.
    EXPECT_NEAR(xi, expected_xi, 5e-6) << "line " << j;
    EXPECT_NEAR(magnitude, expected, 5e-6 * expected) << "line " << j;
  }
}

TEST(FormatSpectrumTxt, MatchesTheReferenceProgramForRaskar) {
  const std::vector<std::string> ours =
      test::lines_of(format_spectrum_txt(builtin_code("raskar").value().gains, 1.0, 1.0));
  const std::vector<std::string> reference = test::lines_of(
      test::read_file(test::fixture_path("camera_numerical_raskar_v1_noisefree/spectrum.txt")));
  ASSERT_EQ(ours.size(), reference.size());
  for (std::size_t j = 0; j < ours.size(); ++j) {
    std::istringstream a(ours[j]), b(reference[j]);
    double xi_a, k_a, xi_b, k_b;
    ASSERT_TRUE(a >> xi_a >> k_a);
    ASSERT_TRUE(b >> xi_b >> k_b);
    // The reference steps xi in single precision (float accumulation
    // reproduces its file to 4e-6): its printed xi may differ by one unit in
    // the sixth digit, and |K| by up to 5e-5 relative.
    EXPECT_NEAR(xi_a, xi_b, 2e-5) << "line " << j;
    EXPECT_NEAR(k_a, k_b, 1e-4 * std::max(1.0, k_b)) << "line " << j;
  }
}

// ---------------------------------------------------------------------------
// report.json

TEST(ReportJson, HasEveryDocumentedKey) {
  const SimulationReport report = small_report();
  const json j = report_json(report, "some/input.png");
  const std::vector<std::pair<std::string, std::vector<std::string>>> keys = {
      {"input", {"path", "width", "height", "channels"}},
      {"parameters", {"code", "code_length", "mode", "velocity", "dt", "snr", "seed", "noise"}},
      {"geometry",
       {"blur_length", "observed_width", "output_width", "rmse_columns", "rmse_ci_columns"}},
      {"metrics", {"rmse", "psnr", "rmse_ci", "psnr_ci"}},
      {"kernel", {"min_abs", "min_abs_xi", "invertible"}},
      {"prediction",
       {"rmse_noise_free", "noise", "rmse", "sigma", "rmse_stationary", "snr_level100"}},
  };
  for (const auto& [section, names] : keys) {
    ASSERT_TRUE(j.contains(section)) << section;
    ASSERT_TRUE(j[section].is_object()) << section;
    for (const std::string& name : names) {
      EXPECT_TRUE(j[section].contains(name)) << section << "." << name;
    }
  }
  ASSERT_TRUE(j["geometry"]["rmse_columns"].is_array());
  ASSERT_TRUE(j["geometry"]["rmse_ci_columns"].is_array());
  EXPECT_EQ(j["geometry"]["rmse_columns"].size(), 2u);
  EXPECT_EQ(j["geometry"]["rmse_ci_columns"].size(), 2u);
}

TEST(ReportJson, ValuesAreThoseOfTheReport) {
  const SimulationReport report = small_report();
  const json j = report_json(report, "some/input.png");
  EXPECT_EQ(j["input"]["path"], "some/input.png");
  EXPECT_EQ(j["input"]["width"], 64);
  EXPECT_EQ(j["input"]["height"], 8);
  EXPECT_EQ(j["input"]["channels"], 1);
  EXPECT_EQ(j["parameters"]["code"], "short");
  EXPECT_EQ(j["parameters"]["code_length"], 4);
  EXPECT_EQ(j["parameters"]["mode"], "numerical");
  EXPECT_EQ(j["parameters"]["noise"], "poisson");
  EXPECT_EQ(j["parameters"]["velocity"], 1.0);
  EXPECT_EQ(j["parameters"]["dt"], 1.0);
  EXPECT_EQ(j["parameters"]["snr"], 100.0);
  EXPECT_EQ(j["parameters"]["seed"], 3u);
  EXPECT_EQ(j["geometry"]["blur_length"], 4);
  EXPECT_EQ(j["geometry"]["observed_width"], 60);
  EXPECT_EQ(j["geometry"]["output_width"], 52);
  EXPECT_EQ(j["geometry"]["rmse_columns"], json::array({12, 40}));
  EXPECT_EQ(j["geometry"]["rmse_ci_columns"], json::array({4, 48}));
  EXPECT_EQ(j["metrics"]["rmse"], report.metrics.rmse);
  EXPECT_EQ(j["metrics"]["psnr"], report.metrics.psnr);
  EXPECT_EQ(j["metrics"]["rmse_ci"], report.metrics.rmse_ci);
  EXPECT_EQ(j["metrics"]["psnr_ci"], report.metrics.psnr_ci);
  EXPECT_EQ(j["kernel"]["min_abs"], report.kernel.min_abs);
  EXPECT_EQ(j["kernel"]["min_abs_xi"], report.kernel.min_abs_xi);
  EXPECT_EQ(j["kernel"]["invertible"], true);
  EXPECT_EQ(j["prediction"]["rmse_noise_free"], report.prediction.rmse_noise_free);
  EXPECT_EQ(j["prediction"]["sigma"], report.prediction.sigma);
  EXPECT_EQ(j["prediction"]["rmse"], report.prediction.rmse);
  EXPECT_EQ(j["prediction"]["noise"], report.prediction.noise);
  EXPECT_EQ(j["prediction"]["rmse_stationary"], report.prediction.rmse_stationary);
  EXPECT_EQ(j["prediction"]["snr_level100"], report.prediction.snr_level100);
}

TEST(ReportJson, LargestSeedIsKeptExactly) {
  const std::uint64_t seed = std::numeric_limits<std::uint64_t>::max();
  const json j = report_json(small_report({1.0, 0.0, 1.0, 1.0}, seed), "in.png");
  ASSERT_TRUE(j["parameters"]["seed"].is_number_unsigned());
  EXPECT_EQ(j["parameters"]["seed"].get<std::uint64_t>(), seed);
  // Through the text too.
  EXPECT_EQ(json::parse(j.dump())["parameters"]["seed"].get<std::uint64_t>(), seed);
}

TEST(ReportJson, InfiniteValuesAreNull) {
  // {1, 1, 1, 1} at v = 1 has zeros at xi = pi / 2 and pi: not invertible.
  SimulationReport report = small_report({1.0, 1.0, 1.0, 1.0});
  ASSERT_FALSE(report.kernel.invertible);
  ASSERT_TRUE(std::isinf(report.prediction.rmse));
  report.metrics.rmse = 0.0;  // a perfect restoration: PSNR is infinite
  report.metrics.psnr = std::numeric_limits<double>::infinity();
  report.metrics.rmse_ci = std::numeric_limits<double>::quiet_NaN();
  report.metrics.psnr_ci = std::numeric_limits<double>::infinity();
  const json j = report_json(report, "in.png");
  EXPECT_TRUE(j["metrics"]["psnr"].is_null());
  EXPECT_TRUE(j["metrics"]["psnr_ci"].is_null());
  EXPECT_TRUE(j["metrics"]["rmse_ci"].is_null());
  EXPECT_EQ(j["metrics"]["rmse"], 0.0);
  EXPECT_TRUE(j["prediction"]["rmse"].is_null());
  EXPECT_TRUE(j["prediction"]["sigma"].is_null());
  EXPECT_TRUE(j["prediction"]["noise"].is_null());
  EXPECT_TRUE(j["prediction"]["rmse_stationary"].is_null());
  EXPECT_EQ(j["kernel"]["invertible"], false);
  // And the text is valid JSON with a null where the infinity was.
  const json parsed = json::parse(j.dump(2));
  EXPECT_TRUE(parsed["prediction"]["rmse"].is_null());
}

// ---------------------------------------------------------------------------
// write_outputs

TEST(OutputFileNames, AreTheNineDocumentedFilesByDefault) {
  EXPECT_EQ(sorted(output_file_names()),
            sorted({"observed.png", "restored.png", "groundtruth.png", "residual.png", "code.txt",
                    "spectrum.txt", "report.json", "code.png", "spectrum.png"}));
}

TEST(OutputFileNames, FollowTheOptions) {
  const std::vector<std::string> base = {"observed.png", "restored.png", "groundtruth.png",
                                         "residual.png", "code.txt",     "spectrum.txt",
                                         "report.json"};
  EXPECT_EQ(sorted(output_file_names({false, false, false})), sorted(base));
  std::vector<std::string> all = base;
  for (const char* name : {"code.png", "spectrum.png", "sheet.png", "report.html"}) {
    all.push_back(name);
  }
  EXPECT_EQ(sorted(output_file_names({true, true, true})), sorted(all));
  std::vector<std::string> page_only = base;
  page_only.push_back("report.html");
  EXPECT_EQ(sorted(output_file_names({false, false, true})), sorted(page_only));
}

TEST(FigureSheetOfARun, ObservedRestoredAndResidualSideBySide) {
  const SimulationReport report = small_report();
  const std::vector<std::uint8_t> png = figure_sheet_png(report, small_input());
  const Image sheet = decode_png(png.data(), png.size(), "sheet");
  ASSERT_EQ(sheet.width, kSheetMargin + 3 * (52 + kSheetMargin));
  // The residual's scale under the panels.
  ASSERT_EQ(sheet.height, kSheetHeaderHeight + 8 + kSheetMargin + kSheetScaleHeight);
  ASSERT_EQ(sheet.channels, 1);
  const Image* panels[] = {&report.observed, &report.restored};
  for (int i = 0; i < 2; ++i) {
    const int left = kSheetMargin + i * (52 + kSheetMargin);
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 52; ++x) {
        ASSERT_EQ(sheet.at(0, kSheetHeaderHeight + y, left + x),
                  std::clamp(std::round(panels[i]->at(0, y, x)), 0.0, 255.0))
            << "panel " << i << " x " << x << " y " << y;
      }
    }
  }
}

// The residual panel shows d = ground truth - restored as 127.5 + 127.5 d / R:
// 0 at mid-gray, linear, symmetric, nothing clipped (R >= max |d|), and R a
// round number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6 or 8 times a power of ten)
// within a factor 4/3 of max |d|.
TEST(FigureSheetOfARun, ResidualOnASymmetricScale) {
  const SimulationReport report = small_report();
  const std::vector<std::uint8_t> png = figure_sheet_png(report, small_input());
  const Image sheet = decode_png(png.data(), png.size(), "sheet");
  const Image truth = groundtruth_image(small_input(), report);
  const int left = kSheetMargin + 2 * (52 + kSheetMargin);
  double dd = 0.0, dg = 0.0, largest = 0.0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 52; ++x) {
      const double d = truth.at(0, y, x) - report.restored.at(0, y, x);
      dd += d * d;
      dg += d * (sheet.at(0, kSheetHeaderHeight + y, left + x) - 127.5);
      largest = std::max(largest, std::abs(d));
    }
  }
  ASSERT_GT(largest, 0.0);
  const double range = 127.5 * dd / dg;  // least squares: gray - 127.5 = 127.5 d / R
  EXPECT_GE(range, largest * 0.99);
  EXPECT_LT(range, largest * 4.0 / 3.0 * 1.01);
  const double step = range / std::pow(10.0, std::floor(std::log10(range)));
  EXPECT_NEAR(step, std::round(step * 10.0) / 10.0, 0.02) << "R = " << range;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 52; ++x) {
      const double d = truth.at(0, y, x) - report.restored.at(0, y, x);
      EXPECT_NEAR(sheet.at(0, kSheetHeaderHeight + y, left + x), 127.5 + 127.5 * d / range, 0.6)
          << "x " << x << " y " << y;
    }
  }
}

TEST(WriteFileAtomically, WritesReplacesAndLeavesNoTemporary) {
  test::TempDir dir;
  write_file_atomically(dir / "a.png", "first");
  EXPECT_EQ(test::read_file(dir / "a.png"), "first");
  write_file_atomically(dir / "a.png", "second");
  EXPECT_EQ(test::read_file(dir / "a.png"), "second");
  EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{"a.png"});
  fs::create_directory(dir / "d.png");
  EXPECT_TRUE(test::throws_error([&] { write_file_atomically(dir / "d.png", "x"); },
                                 ErrorKind::kRuntime, {"d.png", "it is a directory"}));
  EXPECT_TRUE(test::throws_error([&] { write_file_atomically(dir / "no/such/dir/x.png", "x"); },
                                 ErrorKind::kRuntime, {"x.png"}));
  EXPECT_EQ(test::list_directory(dir.path()), (std::vector<std::string>{"a.png", "d.png"}));
}

class WriteOutputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { report_ = new SimulationReport(small_report()); }
  static void TearDownTestSuite() {
    delete report_;
    report_ = nullptr;
  }
  static const SimulationReport& report() { return *report_; }

  // Every output file of `outdir` has the content of a fresh write.
  void expect_complete_outputs(const fs::path& outdir, const std::string& input_path) {
    for (const auto& [name, bytes] : expected_files(report(), input_path)) {
      EXPECT_TRUE(test::read_file(outdir / name) == bytes) << name << " differs";
    }
    const json written = json::parse(test::read_file(outdir / "report.json"));
    EXPECT_EQ(written, report_json(report(), input_path));
  }

  test::TempDir dir_;

 private:
  static SimulationReport* report_;
};
SimulationReport* WriteOutputs::report_ = nullptr;

TEST_F(WriteOutputs, WritesExactlyTheListedFilesIntoANewDirectory) {
  const fs::path outdir = dir_ / "nested/out";
  write_outputs(outdir, report(), small_input(), "input.png");
  EXPECT_EQ(test::list_directory(outdir), sorted(output_file_names()));
  expect_complete_outputs(outdir, "input.png");
  // No staging leftovers next to the directory either.
  EXPECT_EQ(test::list_directory(dir_ / "nested"), std::vector<std::string>{"out"});
  const Image observed = read_png(outdir / "observed.png");
  EXPECT_EQ(observed.width, 52);
  EXPECT_EQ(observed.height, 8);
  EXPECT_EQ(observed.channels, 1);
}

TEST_F(WriteOutputs, PlotsAreValidPngsOfTheDocumentedSize) {
  write_outputs(dir_.path(), report(), small_input(), "input.png");
  for (const char* name : {"code.png", "spectrum.png"}) {
    const Image plot = read_png(dir_ / name);
    EXPECT_EQ(plot.width, kPlotWidth) << name;
    EXPECT_EQ(plot.height, kPlotHeight) << name;
    EXPECT_EQ(plot.channels, 3) << name;
  }
}

TEST_F(WriteOutputs, OptionsChooseTheOptionalFiles) {
  const OutputOptions none{false, false, false};
  write_outputs(dir_ / "none", report(), small_input(), "input.png", none);
  EXPECT_EQ(test::list_directory(dir_ / "none"), sorted(output_file_names(none)));
  EXPECT_FALSE(fs::exists(dir_ / "none/code.png"));

  const OutputOptions all{true, true, true};
  write_outputs(dir_ / "all", report(), small_input(), "some/input.png", all);
  EXPECT_EQ(test::list_directory(dir_ / "all"), sorted(output_file_names(all)));
  expect_complete_outputs(dir_ / "all", "some/input.png");
  EXPECT_TRUE(test::read_file(dir_ / "all/report.html") ==
              html_report(report(), "some/input.png", output_file_names(all)));
  EXPECT_TRUE(test::read_file(dir_ / "all/sheet.png") ==
              as_string(figure_sheet_png(report(), small_input())));
}

TEST_F(WriteOutputs, WritesIntoAnExistingEmptyDirectory) {
  write_outputs(dir_.path(), report(), small_input(), "input.png");
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(output_file_names()));
}

TEST_F(WriteOutputs, OutdirThatIsARegularFileIsRefused) {
  const fs::path file = dir_ / "not-a-directory";
  test::write_file(file, "precious content\n");
  EXPECT_TRUE(test::throws_error([&] { write_outputs(file, report(), small_input(), "input.png"); },
                                 ErrorKind::kRuntime, {file.string(), "is not a directory"}));
  EXPECT_EQ(test::read_file(file), "precious content\n");
  EXPECT_EQ(test::list_directory(dir_.path()), std::vector<std::string>{"not-a-directory"});
}

TEST_F(WriteOutputs, RefusesToOverwriteTheInput) {
  const std::string input_bytes = png_bytes(test::make_test_image(64, 8, 1, 5));
  test::write_file(dir_ / "observed.png", input_bytes);
  // The same file, spelled three ways.
  const std::vector<std::pair<fs::path, std::string>> spellings = {
      {dir_.path(), (dir_ / "observed.png").string()},
      {dir_.path(), (dir_.path() / "." / "observed.png").string()},
      {dir_.path() / ".", (dir_ / "observed.png").string()},
  };
  for (const auto& spelling : spellings) {
    // Named references: clang 14 cannot capture structured bindings in a lambda.
    const fs::path& outdir = spelling.first;
    const std::string& input_path = spelling.second;
    EXPECT_TRUE(
        test::throws_error([&] { write_outputs(outdir, report(), small_input(), input_path); },
                           ErrorKind::kRuntime, {"refusing to overwrite the input", input_path}))
        << outdir << " / " << input_path;
    EXPECT_TRUE(test::read_file(dir_ / "observed.png") == input_bytes);
    EXPECT_EQ(test::list_directory(dir_.path()), std::vector<std::string>{"observed.png"});
  }
}

TEST_F(WriteOutputs, InputWithAnOutputNameElsewhereIsFine) {
  // An input called observed.png in another directory is not in the way.
  test::write_file(dir_ / "observed.png", "input");
  const fs::path outdir = dir_ / "out";
  write_outputs(outdir, report(), small_input(), (dir_ / "observed.png").string());
  EXPECT_EQ(test::read_file(dir_ / "observed.png"), "input");
  EXPECT_EQ(test::list_directory(outdir), sorted(output_file_names()));
}

TEST_F(WriteOutputs, ReplacesPreviousOutputsOnSuccess) {
  for (const std::string& name : output_file_names()) test::write_file(dir_ / name, "old " + name);
  test::write_file(dir_ / "unrelated.txt", "keep me");
  write_outputs(dir_.path(), report(), small_input(), "input.png");
  expect_complete_outputs(dir_.path(), "input.png");
  EXPECT_EQ(test::read_file(dir_ / "unrelated.txt"), "keep me");
  std::vector<std::string> expected = output_file_names();
  expected.push_back("unrelated.txt");
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(expected));
}

TEST_F(WriteOutputs, KeepsPreviousOutputsOnFailure) {
  // report.json is a directory: writing it must fail, and then no other
  // output may have been replaced.
  for (const std::string& name : output_file_names()) {
    if (name != "report.json") test::write_file(dir_ / name, "old " + name);
  }
  fs::create_directory(dir_ / "report.json");
  EXPECT_TRUE(
      test::throws_error([&] { write_outputs(dir_.path(), report(), small_input(), "input.png"); },
                         ErrorKind::kRuntime, {"report.json", "it is a directory"}));
  for (const std::string& name : output_file_names()) {
    if (name != "report.json") EXPECT_EQ(test::read_file(dir_ / name), "old " + name) << name;
  }
  EXPECT_TRUE(fs::is_directory(dir_ / "report.json"));
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(output_file_names()));
}

TEST_F(WriteOutputs, KeepsPreviousOutputsWhenTheInputIsInTheWay) {
  for (const std::string& name : output_file_names()) test::write_file(dir_ / name, "old " + name);
  EXPECT_TRUE(test::throws_error(
      [&] {
        write_outputs(dir_.path(), report(), small_input(), (dir_ / "restored.png").string());
      },
      ErrorKind::kRuntime, {"refusing to overwrite the input"}));
  for (const std::string& name : output_file_names()) {
    EXPECT_EQ(test::read_file(dir_ / name), "old " + name) << name;
  }
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(output_file_names()));
}

TEST_F(WriteOutputs, RefusesToOverwriteAnotherInputSuchAsTheCodeFile) {
  const std::string hand_written = "# my code\n1 0 1 1\n";
  test::write_file(dir_ / "code.txt", hand_written);
  test::write_file(dir_ / "restored.png", "old restored.png");
  const std::string code_path = (dir_ / "code.txt").string();
  OutputOptions options;
  options.other_inputs = {code_path};
  EXPECT_TRUE(test::throws_error(
      [&] { write_outputs(dir_.path(), report(), small_input(), "input.png", options); },
      ErrorKind::kRuntime, {"refusing to overwrite the input", code_path}));
  EXPECT_EQ(test::read_file(dir_ / "code.txt"), hand_written);
  EXPECT_EQ(test::read_file(dir_ / "restored.png"), "old restored.png");
  EXPECT_EQ(test::list_directory(dir_.path()),
            (std::vector<std::string>{"code.txt", "restored.png"}));
}

TEST_F(WriteOutputs, NonUtf8InputPathIsWrittenWithReplacementCharacters) {
  // A file name is bytes; nlohmann::json refuses to dump invalid UTF-8 unless told.
  const std::string latin1 = "caf\xe9.png";
  write_outputs(dir_.path(), report(), small_input(), latin1);
  const json written = json::parse(test::read_file(dir_ / "report.json"));
  EXPECT_EQ(written["input"]["path"], "caf\xef\xbf\xbd.png");  // U+FFFD
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(output_file_names()));
}

TEST_F(WriteOutputs, StagingNeverReplacesOrRemovesOtherFiles) {
  // Hidden files named as a staging file of this process might be: staging
  // must create new files only, even when a write then fails.
  const std::string pid = std::to_string(::getpid());
  std::vector<std::string> decoys;
  for (const std::string& name : output_file_names()) {
    for (const std::string& suffix : {".fssim-tmp-" + pid, ".fssim-" + pid + "-0.tmp"}) {
      decoys.push_back("." + name);
      decoys.back() += suffix;
    }
  }
  for (const std::string& decoy : decoys) test::write_file(dir_ / decoy, "decoy " + decoy);
  write_outputs(dir_.path(), report(), small_input(), "input.png");
  expect_complete_outputs(dir_.path(), "input.png");
  for (const std::string& decoy : decoys) {
    EXPECT_EQ(test::read_file(dir_ / decoy), "decoy " + decoy) << decoy;
  }
  std::vector<std::string> expected = output_file_names();
  expected.insert(expected.end(), decoys.begin(), decoys.end());
  EXPECT_EQ(test::list_directory(dir_.path()), sorted(expected));
}

TEST_F(WriteOutputs, EmptyOutdirIsAUsageError) {
  EXPECT_TRUE(test::throws_error([&] { write_outputs("", report(), small_input(), "input.png"); },
                                 ErrorKind::kUsage, {"output directory"}));
}

// A directory named as a staging directory of fssim's, made as a killed run
// would have left it: mode 1700 (fssim's mark), the marker file, and the
// manifest `commit` when not empty.
fs::path forge_stage(const fs::path& outdir, const std::string& name, const std::string& commit) {
  const fs::path stage = outdir / name;
  fs::create_directory(stage);
  EXPECT_EQ(::chmod(stage.c_str(), 01700), 0);
  test::write_file(stage / ".fssim-staging",
                   "staging directory of an fssim run: removed by the next run\n");
  if (!commit.empty()) test::write_file(stage / ".fssim-commit", commit);
  return stage;
}

TEST_F(WriteOutputs, UnmarkedStagingDirectoriesAreLeftAloneEvenEmpty) {
  // A user's empty directories with a staging name, without fssim's mark.
  const fs::path outdir = dir_ / "out";
  fs::create_directories(outdir / ".fssim-stage-mine");
  fs::create_directory(outdir / ".fssim-stage-1-2-3");
  ASSERT_EQ(::chmod((outdir / ".fssim-stage-1-2-3").c_str(), 0700), 0);
  write_outputs(outdir, report(), small_input(), "input.png");
  EXPECT_TRUE(fs::is_directory(outdir / ".fssim-stage-mine"));
  EXPECT_TRUE(fs::is_directory(outdir / ".fssim-stage-1-2-3"));
  // A marked one left empty (a run killed as it created it) is fssim's: removed.
  fs::create_directory(outdir / ".fssim-stage-4-5-6");
  ASSERT_EQ(::chmod((outdir / ".fssim-stage-4-5-6").c_str(), 01700), 0);
  write_outputs(outdir, report(), small_input(), "input.png");
  EXPECT_FALSE(fs::exists(outdir / ".fssim-stage-4-5-6"));
  EXPECT_TRUE(fs::is_directory(outdir / ".fssim-stage-mine"));
}

TEST_F(WriteOutputs, AForgedManifestMovesAndRemovesNothing) {
  const fs::path outdir = dir_ / "out";
  fs::create_directories(outdir);
  test::write_file(outdir / "notes.txt", "my notes");
  test::write_file(dir_ / "victim.txt", "outside");
  const fs::path remove = forge_stage(outdir, ".fssim-stage-1-1-1", "0 notes.txt\n");
  const fs::path move_in = forge_stage(outdir, ".fssim-stage-2-2-2", "0 ../victim.txt\n");
  // A new file of a name that is no output, published by its inode.
  const fs::path inode = forge_stage(outdir, ".fssim-stage-3-3-3", "");
  test::write_file(inode / "payload.txt", "payload");
  struct stat st {};
  ASSERT_EQ(::stat((inode / "payload.txt").c_str(), &st), 0);
  test::write_file(inode / ".fssim-commit", std::to_string(st.st_ino) + " payload.txt\n");
  // Uncommitted, but holding a file that is no output: not provably fssim's.
  const fs::path stranger = forge_stage(outdir, ".fssim-stage-4-4-4", "");
  test::write_file(stranger / "letter.txt", "keep");
  write_outputs(outdir, report(), small_input(), "input.png");
  EXPECT_EQ(test::read_file(outdir / "notes.txt"), "my notes");
  EXPECT_EQ(test::read_file(dir_ / "victim.txt"), "outside");
  EXPECT_FALSE(fs::exists(outdir / "victim.txt"));
  EXPECT_FALSE(fs::exists(outdir / "payload.txt"));
  EXPECT_EQ(test::read_file(stranger / "letter.txt"), "keep");
  for (const fs::path& stage : {remove, move_in, inode, stranger}) {
    EXPECT_TRUE(fs::exists(stage / ".fssim-staging")) << stage;
  }
  expect_complete_outputs(outdir, "input.png");
}

TEST(WriteOutputSet, AFailedWriteRemovesEveryDirectoryItCreated) {
  test::TempDir dir;
  fs::create_directory(dir / "old");
  const std::vector<OutputFile> failing = {
      {"a.txt", "a", {}}, {"b.txt", "", []() -> std::string { throw_runtime_error("no b"); }}};
  for (const fs::path& outdir : {dir / "new/a/b", dir / "old/c/d/", dir / "old/e/./f"}) {
    EXPECT_TRUE(test::throws_error([&] { write_output_set(outdir, failing, {}); },
                                   ErrorKind::kRuntime, {"no b"}));
  }
  EXPECT_EQ(test::list_directory(dir.path()), std::vector<std::string>{"old"});
  EXPECT_TRUE(test::list_directory(dir / "old").empty());
  // An existing directory stays, and so does one that became non-empty.
  write_output_set(dir / "old/g", {{"a.txt", "a", {}}}, {});
  EXPECT_TRUE(test::throws_error([&] { write_output_set(dir / "old/g/h", failing, {}); },
                                 ErrorKind::kRuntime));
  EXPECT_EQ(test::list_directory(dir / "old/g"), std::vector<std::string>{"a.txt"});
}

// A maker that notes its file's name in `made` (under `mutex`) and makes its name as bytes.
std::function<std::string()> noting_maker(const std::string& name, std::vector<std::string>& made,
                                          std::mutex& mutex) {
  return [&made, &mutex, name] {
    const std::lock_guard<std::mutex> lock(mutex);
    made.push_back(name);
    return name;
  };
}

TEST(WriteOutputSet, FilesAreMadeByDecreasingRankThenInFileOrder) {
  test::TempDir dir;
  std::vector<std::string> made;
  std::mutex mutex;
  std::vector<OutputFile> files;
  const std::vector<std::pair<std::string, int>> ranked = {
      {"a.txt", 0}, {"b.txt", 2}, {"c.txt", 0}, {"d.txt", 1}, {"e.txt", 2}};
  files.reserve(ranked.size());
  for (const auto& [name, rank] : ranked) {
    files.push_back({name, {}, noting_maker(name, made, mutex), rank});
  }
  write_output_set(dir / "out", files, {}, {}, /*threads=*/1);
  EXPECT_EQ(made, (std::vector<std::string>{"b.txt", "e.txt", "d.txt", "a.txt", "c.txt"}));
  for (const auto& [name, rank] : ranked) EXPECT_EQ(test::read_file(dir / "out" / name), name);
  // On two threads too, every file is made once, with its own bytes.
  made.clear();
  write_output_set(dir / "out2", files, {}, {}, /*threads=*/2);
  EXPECT_EQ(made.size(), ranked.size());
  for (const auto& [name, rank] : ranked) EXPECT_EQ(test::read_file(dir / "out2" / name), name);
}

TEST(WriteOutputSet, TheErrorThrownIsTheFirstInFileOrderWhateverTheRanks) {
  test::TempDir dir;
  const auto failing = [](const std::string& what) {
    return [what]() -> std::string { throw_runtime_error(what); };
  };
  // b.txt is made first (its rank) and fails first, but a.txt comes first in the set.
  const std::vector<OutputFile> files = {
      {"a.txt", {}, failing("no a"), 0}, {"b.txt", {}, failing("no b"), 5}, {"c.txt", "c", {}}};
  for (const int threads : {1, 2}) {
    const std::optional<Error> error =
        test::error_of([&] { write_output_set(dir / "out", files, {}, {}, threads); });
    ASSERT_TRUE(error.has_value()) << threads;
    EXPECT_NE(std::string(error->what()).find("no a"), std::string::npos) << error->what();
    EXPECT_FALSE(fs::exists(dir / "out")) << threads;
  }
}

}  // namespace
}  // namespace fss

namespace fss {
namespace {

// A run that streams its observed rows into an ObservedPng8 instead of
// keeping them, as fssim does; `keep` also keeps them for comparison (a
// second run of the same options keeps the same rows).
struct StreamedRun {
  explicit StreamedRun(const Image& input, bool keep = false, int threads = 2)
      : observed(input.height, input.channels) {
    SimulationOptions options;
    options.seed = 11;
    options.threads = threads;
    report = Simulate(options, input, *builtin_code("raskar"), &observed);
    if (keep) report.observed = Simulate(options, input, *builtin_code("raskar")).observed;
  }
  ObservedPng8 observed;
  SimulationReport report;
};

TEST(ObservedPng8, EncodesTheBytesOfTheKeptImage) {
  for (const int channels : {1, 3}) {
    const Image input = test::make_test_image(480, 9, channels, 6);
    const StreamedRun run(input, /*keep=*/true);
    ASSERT_EQ(run.observed.rows_stored(), 9 * channels);
    EXPECT_EQ(run.observed.width(), run.report.observed.width);
    const std::vector<std::uint8_t> png = encode_png8(run.report.observed);
    EXPECT_TRUE(run.observed.encode() == png) << channels;
    const std::string file = run.observed.encode_string();
    EXPECT_TRUE(file == std::string(png.begin(), png.end())) << channels;
  }
}

TEST(ObservedPng8, RoundsAndClampsLikeTheEncoder) {
  ObservedPng8 observed(1, 1);
  const std::vector<double> row = {
      -3.0, -0.5, 0.49, 0.5, 127.5, 254.5, 255.4, 300.0, std::numeric_limits<double>::quiet_NaN()};
  observed.store_row(0, 0, row);
  const std::vector<std::uint8_t> png = observed.encode();
  const Image decoded = decode_png(png.data(), png.size(), "observed");
  const std::vector<double> expected = {0, 0, 0, 1, 128, 255, 255, 255, 0};
  EXPECT_EQ(decoded.data, expected);
  for (std::size_t i = 0; i < row.size(); ++i) EXPECT_EQ(png8_sample(row[i]), expected[i]) << i;
}

TEST(ObservedPng8, RefusesRowsThatDoNotFitAndIncompleteImages) {
  ObservedPng8 observed(2, 1);
  const std::vector<double> row(5, 1.0);
  observed.store_row(0, 0, row);
  const std::vector<double> short_row(4, 1.0);
  EXPECT_TRUE(test::throws_error([&] { observed.store_row(0, 1, short_row); }, ErrorKind::kUsage,
                                 {"row 1 of channel 0 with 4 values does not fit a 5 x 2 x 1"}));
  EXPECT_TRUE(test::throws_error([&] { observed.store_row(0, 2, row); }, ErrorKind::kUsage,
                                 {"row 2 of channel 0", "does not fit"}));
  EXPECT_TRUE(test::throws_error([&] { observed.store_row(1, 0, row); }, ErrorKind::kUsage,
                                 {"row 0 of channel 1", "does not fit"}));
  EXPECT_TRUE(
      test::throws_error([&] { observed.encode(); }, ErrorKind::kUsage, {"1 of 2 observed rows"}));
  EXPECT_TRUE(test::throws_error([&] { observed.encode_string(); }, ErrorKind::kUsage,
                                 {"1 of 2 observed rows"}));
  observed.store_row(0, 1, row);
  EXPECT_NO_THROW(observed.encode());
  EXPECT_TRUE(test::throws_error([&] { observed.store_row(0, 1, row); }, ErrorKind::kUsage,
                                 {"row 1 of channel 0 was stored twice"}));
  EXPECT_TRUE(test::throws_error([] { ObservedPng8(0, 1); }, ErrorKind::kUsage, {"height 0"}));
  EXPECT_TRUE(test::throws_error([] { ObservedPng8(3, 2); }, ErrorKind::kUsage, {"2 channels"}));
}

TEST(ObservedPng8, WriteOutputsGivesTheSameFilesWithoutTheKeptImage) {
  const Image input = test::make_test_image(480, 9, 3, 6);
  const StreamedRun kept(input, /*keep=*/true);
  const StreamedRun streamed(input, /*keep=*/false);
  ASSERT_TRUE(streamed.report.observed.data.empty());
  test::TempDir dir;
  write_outputs(dir / "kept", kept.report, input, "input.png");
  write_outputs(dir / "streamed", streamed.report, streamed.observed, input, "input.png");
  for (const std::string& name : output_file_names()) {
    EXPECT_TRUE(test::read_file(dir / "kept" / name) == test::read_file(dir / "streamed" / name))
        << name;
  }
}

TEST(ObservedPng8, WithoutEitherObservedImageNothingIsWritten) {
  const Image input = test::make_test_image(480, 4, 1, 6);
  const StreamedRun streamed(input);
  test::TempDir dir;
  EXPECT_TRUE(test::throws_error(
      [&] { write_outputs(dir / "out", streamed.report, input, "input.png"); }, ErrorKind::kUsage,
      {"observed.png: the report keeps no observed image", "ObservedPng8"}));
  EXPECT_FALSE(fs::exists(dir / "out"));
  // Rows of another image are refused.
  const StreamedRun other(test::make_test_image(480, 5, 1, 6));
  EXPECT_TRUE(test::throws_error(
      [&] { write_outputs(dir / "out", streamed.report, other.observed, input, "input.png"); },
      ErrorKind::kUsage, {"x 5 x 1 image, the report's outputs are"}));
  EXPECT_FALSE(fs::exists(dir / "out"));
  // The sheet shows the observed image: it needs the kept one.
  OutputOptions sheet;
  sheet.sheet = true;
  EXPECT_TRUE(test::throws_error(
      [&] {
        write_outputs(dir / "out", streamed.report, streamed.observed, input, "input.png", sheet);
      },
      ErrorKind::kUsage, {"sheet.png needs the observed image"}));
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace fss

namespace fss {
namespace {

// Plots drawn ahead are the bytes write_outputs draws itself, including with
// a restore velocity (the marked minimum is that of the inverted kernel).
TEST(RenderRunPlots, AreTheBytesWriteOutputsDraws) {
  const Image input = test::make_test_image(640, 6, 1, 2);
  for (const std::optional<double> restore : {std::optional<double>(), std::optional(1.3)}) {
    SimulationOptions options;
    options.velocity_px_per_slot = -1.0;
    options.restore_velocity_px_per_slot = restore;
    options.dt = 0.9;
    const ShutterCode code = *builtin_code("raskar");
    const RunPlots plots = render_run_plots(code, options);
    const SimulationReport report = Simulate(options, input, code);
    test::TempDir dir;
    write_outputs(dir / "drawn", report, input, "input.png");
    PlotsAhead given;
    given.drawn = plots;
    write_outputs(dir / "given", report, input, "input.png", OutputOptions{}, given);
    for (const char* name : {"code.png", "spectrum.png"}) {
      const std::string drawn = test::read_file(dir / "drawn" / name);
      EXPECT_TRUE(drawn == test::read_file(dir / "given" / name)) << name;
      EXPECT_TRUE(drawn ==
                  as_string(std::string(name) == "code.png" ? plots.code_png : plots.spectrum_png))
          << name;
    }
  }
}

TEST(RenderRunPlots, PlotsOfAnotherRunAreRefused) {
  const Image input = test::make_test_image(480, 4, 1, 2);
  SimulationOptions options;
  const SimulationReport report = Simulate(options, input, *builtin_code("raskar"));
  // What differs, and how the message says it.
  std::vector<std::pair<std::string, RunPlots>> wrong;
  wrong.emplace_back("code 'mip', the run's is 'raskar'",
                     render_run_plots(*builtin_code("mip"), options));
  ShutterCode other_gains = *builtin_code("raskar");
  other_gains.gains[0] = 0.5;
  wrong.emplace_back("other gains of code 'raskar'", render_run_plots(other_gains, options));
  options.velocity_px_per_slot = 2.0;
  wrong.emplace_back("velocity 2, the run's is 1",
                     render_run_plots(*builtin_code("raskar"), options));
  options.velocity_px_per_slot = 1.0;
  options.restore_velocity_px_per_slot = 1.5;
  wrong.emplace_back("restore velocity 1.5, the run's is 1",
                     render_run_plots(*builtin_code("raskar"), options));
  options.restore_velocity_px_per_slot.reset();
  options.dt = 0.5;
  wrong.emplace_back("dt 0.5, the run's is 1", render_run_plots(*builtin_code("raskar"), options));
  for (const auto& [what, plots] : wrong) {
    test::TempDir dir;
    PlotsAhead given;
    given.drawn = plots;
    EXPECT_TRUE(test::throws_error(
        [&] { write_outputs(dir / "out", report, input, "input.png", OutputOptions{}, given); },
        ErrorKind::kUsage, {"not for the report's run: drawn for " + what}));
    EXPECT_FALSE(fs::exists(dir / "out")) << what;
  }
}

}  // namespace
}  // namespace fss
