// A consumer of the installed fss linked with `pkg-config --cflags --libs fss`:
// simulates a ramp through the snapshot code without noise, writes every
// output (PNG images, plots drawn by PLplot, report.json) into OUTDIR, reads
// report.json back and checks it against the report.
// Usage: pkgconfig_consumer OUTDIR
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/outputs.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "pkgconfig_consumer: FAILED: %s\n", what.c_str());
    ++failures;
  }
}

// A horizontal ramp from 20 to 220 over 600 columns, 8 rows (the snapshot
// code has L = 52 slots: the measurement windows need 9 L + 1 columns).
fss::Image ramp() {
  fss::Image image(600, 8, 1);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) image.at(0, y, x) = 20.0 + 200.0 * x / (image.width - 1);
  }
  return image;
}

void run(const std::filesystem::path& outdir) {
  const fss::Image input = ramp();
  fss::SimulationOptions options;
  options.noise = fss::NoiseModel::kNone;
  options.threads = 1;
  const fss::SimulationReport report =
      fss::Simulate(options, input, *fss::builtin_code("snapshot"));
  fss::write_outputs(outdir, report, input, "ramp (generated)");

  std::ifstream file(outdir / "report.json");
  const nlohmann::json json = nlohmann::json::parse(file);
  const double rmse = json.at("metrics").at("rmse").get<double>();
  const int width = json.at("geometry").at("output_width").get<int>();
  std::printf("snapshot, ramp 600x8, no noise: RMSE %.6g, output width %d, report.json RMSE %.6g\n",
              report.metrics.rmse, width, rmse);
  check(rmse == report.metrics.rmse, "report.json holds the report's RMSE");
  check(width == report.restored.width, "report.json holds the output width");
  check(json.at("parameters").at("noise") == "none", "report.json records noise none");
  check(report.metrics.rmse < 1.0, "the noise-free restoration of a ramp is within 1 gray level");
  for (const std::string& name : fss::output_file_names()) {
    const auto size =
        std::filesystem::exists(outdir / name) ? std::filesystem::file_size(outdir / name) : 0;
    std::printf("  %s: %ju bytes\n", name.c_str(), static_cast<std::uintmax_t>(size));
    check(size > 0, name + " written");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: pkgconfig_consumer OUTDIR\n");
    return 2;
  }
  try {
    run(argv[1]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pkgconfig_consumer: %s\n", error.what());
    return 1;
  }
  std::printf("pkgconfig_consumer: %s\n", failures == 0 ? "ok" : "FAILED");
  return failures == 0 ? 0 : 1;
}
