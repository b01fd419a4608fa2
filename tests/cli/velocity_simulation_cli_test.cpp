// `fssim --velocity-distribution` and `fssim sweep --velocity-distribution` end to end
// (docs/method.md §13): what they print and record, an infinite expectation said as such, the
// same bytes for any thread count, and the one-line refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;

class VelocitySimulationCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // 900 columns: B = 63 at |v| <= 1.2 leaves the default RMSE window (9B + 1 = 568).
    const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(900, 8, 1));
    test::write_file(input_, std::string(png.begin(), png.end()));
  }

  // `fssim -i IN ARGS -o DIR/NAME`.
  test::CommandResult simulate(const std::string& arguments, const std::string& name = "out") {
    return run_fssim("-i " + quote(input_) + " " + arguments + " -o " + quote(dir_ / name));
  }

  nlohmann::json report(const std::string& name = "out") const {
    return nlohmann::json::parse(test::read_file(dir_ / name / "report.json"));
  }

  void expect_refused(const test::CommandResult& r, int exit_code, const std::string& part) {
    EXPECT_EQ(r.exit_code, exit_code) << r.err;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
  }

  test::TempDir dir_;
  fs::path input_ = dir_.path() / "in.png";
};

bool has_line_starting(const std::string& out, const std::string& start) {
  for (const std::string& line : test::lines_of(out)) {
    if (line.rfind(start, 0) == 0) return true;
  }
  return false;
}

TEST_F(VelocitySimulationCli, PrintsAndRecordsTheDistribution) {
  const test::CommandResult r =
      simulate("--velocity-distribution uniform:0.8:1.2 --trials 4 --no-plots --report");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has_line_starting(r.out,
                                "Velocity distribution: uniform on [0.8, 1.2] "
                                "(uniform:0.8:1.2); trial 1 at velocity "))
      << r.out;
  EXPECT_TRUE(has_line_starting(r.out, "Predicted sqrt(expected MSE): ")) << r.out;
  EXPECT_TRUE(has_line_starting(r.out, "MSE mean over trials: ")) << r.out;
  EXPECT_NE(r.out.find("; predicted expected MSE: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;

  const nlohmann::json j = report();
  EXPECT_TRUE(j["parameters"]["velocity"].is_null());
  EXPECT_TRUE(j["parameters"]["restore_velocity"].is_null());
  EXPECT_EQ(j["parameters"]["velocity_distribution"]["text"], "uniform:0.8:1.2");
  EXPECT_EQ(j["parameters"]["velocity_distribution"]["description"], "uniform on [0.8, 1.2]");
  ASSERT_EQ(j["trials"]["velocities"].size(), 4u);
  for (const auto& v : j["trials"]["velocities"]) {
    EXPECT_TRUE(v.get<double>() >= 0.8 && v.get<double>() <= 1.2) << v;
  }
  EXPECT_TRUE(j["trials"]["mse_mean"].is_number());
  EXPECT_TRUE(j["trials"]["mse_sd"].is_number());
  const nlohmann::json& p = j["prediction"];
  ASSERT_TRUE(p["mse"].is_number());
  EXPECT_DOUBLE_EQ(std::sqrt(p["mse"].get<double>()), p["rmse"].get<double>());
  EXPECT_GT(p["mse_evaluations"].get<int>(), 15);
  EXPECT_TRUE(p["mse_error_estimate"].is_number());
  EXPECT_TRUE(p["mse_infinite_reason"].is_null());
  EXPECT_EQ(j["geometry"]["blur_length"], 63);  // ceil(1.2 x 52)

  const std::string html = test::read_file(dir_ / "out" / "report.html");
  EXPECT_NE(html.find("velocity distribution"), std::string::npos);
  EXPECT_NE(html.find("predicted expected MSE"), std::string::npos);
}

TEST_F(VelocitySimulationCli, ReadsAFileOfVelocitiesAndKeepsIt) {
  const fs::path file = dir_.path() / "velocities.txt";
  const std::string text = "# velocity weight\n0.9 1\n1.1 3\n";
  test::write_file(file, text);
  const test::CommandResult r =
      simulate("--velocity-distribution " + quote(file) + " --trials 3 --restore-velocity 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = report();
  EXPECT_EQ(j["parameters"]["velocity_distribution"]["text"], file.string());
  EXPECT_EQ(j["parameters"]["restore_velocity"], 1.0);
  for (const auto& v : j["trials"]["velocities"]) {
    EXPECT_TRUE(v.get<double>() == 0.9 || v.get<double>() == 1.1) << v;
  }
  EXPECT_EQ(j["prediction"]["mse_evaluations"], 2);  // the exact sum over the two velocities
  EXPECT_TRUE(has_line_starting(r.out, "Restore velocity: 1 (true velocity drawn by each trial)"))
      << r.out;
  EXPECT_EQ(test::read_file(file), text);
  // The file is an input, never written over by an output of the same name.
  const fs::path folder = dir_.path() / "kept";
  fs::create_directories(folder);
  test::write_file(folder / "spectrum.txt", text);
  const test::CommandResult over =
      run_fssim("-i " + quote(input_) + " --velocity-distribution " +
                quote(folder / "spectrum.txt") + " -o " + quote(folder));
  EXPECT_NE(over.exit_code, 0) << over.out;
  EXPECT_EQ(test::read_file(folder / "spectrum.txt"), text);
}

// A code invertible at 0.5 but not at 1.5 (three ones: K = 0 at theta = 2 pi / 3).
TEST_F(VelocitySimulationCli, InfiniteExpectationIsSaidAsSuch) {
  const fs::path code = dir_.path() / "three.txt";
  test::write_file(code, "1 1 1\n");
  const test::CommandResult r =
      simulate("-c " + quote(code) + " --velocity-distribution uniform:0.5:1.5 --trials 6");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has_line_starting(
      r.out, "Predicted RMSE: infinite: code not invertible at velocity 1.5 of the support"))
      << r.out;
  EXPECT_NE(r.out.find("predicted expected MSE: infinite: code not invertible at velocity 1.5 of "
                       "the support"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  const nlohmann::json p = report()["prediction"];
  EXPECT_FALSE(p["finite"].get<bool>());
  EXPECT_TRUE(p["mse"].is_null());
  EXPECT_EQ(p["mse_infinite_reason"], "code not invertible at velocity 1.5 of the support");
}

// Every file, the plots drawn ahead or not, and stdout: the same for 1 and 2 threads.
TEST_F(VelocitySimulationCli, SameBytesForAnyThreadCount) {
  const std::string run = "--velocity-distribution normal:1:0.05 --trials 2 --sheet --report";
  const test::CommandResult one = simulate(run + " --threads 1", "one");
  const test::CommandResult two = simulate(run + " --threads 2", "two");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const std::vector<std::string> files = test::list_directory(dir_ / "one");
  EXPECT_EQ(files, test::list_directory(dir_ / "two"));
  for (const std::string& name : files) {
    if (name == "report.html") continue;  // names its folder
    EXPECT_EQ(test::read_file(dir_ / "one" / name), test::read_file(dir_ / "two" / name)) << name;
  }
  EXPECT_EQ(one.out.substr(0, one.out.find("Outputs:")),
            two.out.substr(0, two.out.find("Outputs:")));
}

TEST_F(VelocitySimulationCli, SweepTakesTheDistribution) {
  const fs::path csv = dir_.path() / "sweep.csv";
  const test::CommandResult r = run_fssim(
      "sweep -i " + quote(input_) +
      " --velocity-distribution uniform:0.9:1.1 --snr 50:100:50 --trials 2 -o " + quote(csv));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = test::lines_of(test::read_file(csv));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,"
            "snr_level100,invertible,status,velocity_distribution,mse_mean,mse_sd,predicted_mse");
  EXPECT_EQ(lines[1].rfind(",50,58,", 0), 0u) << lines[1];
  EXPECT_NE(lines[2].find(",ok,uniform:0.9:1.1,"), std::string::npos) << lines[2];
  EXPECT_NE(r.out.find("velocity uniform:0.9:1.1, snr 100: MSE mean "), std::string::npos) << r.out;
}

TEST_F(VelocitySimulationCli, RefusalsAreOneLine) {
  expect_refused(simulate("--velocity-distribution uniform:0.8:1.2 --velocity 1"), 2,
                 "--velocity-distribution: cannot be used with -v/--velocity");
  expect_refused(simulate("--velocity-distribution uniform:1.2:0.8"), 2, "--velocity-distribution");
  expect_refused(simulate("--velocity-distribution " + quote(dir_.path() / "missing.txt")), 2,
                 "is neither uniform:LO:HI");
  expect_refused(simulate("--velocity-distribution uniform:0.8:1.2 --restoration wiener"), 2,
                 "cannot be used with a velocity distribution");
  expect_refused(simulate("--velocity-distribution uniform:0.8:1.2 --restoration tikhonov"), 2,
                 "cannot be used with a velocity distribution");
  expect_refused(simulate("--velocity-distribution uniform:0:100"), 2,
                 "of the velocity distribution's support");
  const fs::path bad = dir_.path() / "bad.txt";
  test::write_file(bad, "0.9 1\nfast 2\n");
  expect_refused(simulate("--velocity-distribution " + quote(bad)), 1, "bad.txt");
  expect_refused(run_fssim("sweep -i " + quote(input_) + " -o " + quote(dir_ / "s.csv") +
                           " --velocity-distribution uniform:0.8:1.2 -v 1:2:1"),
                 2, "--velocity-distribution: cannot be used with -v/--velocity");
}

}  // namespace
}  // namespace fss
