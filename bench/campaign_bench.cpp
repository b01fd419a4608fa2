// Campaign overhead: the same simulations run by fss::RunCampaign (journal,
// fsync per setting, result files; each kernel computed once per code and
// velocity, SimulationPlanCache) and one by one with fss::Simulate in one
// process (image decoded once, codes loaded once, each run computing its
// kernel). Prints the median and
// the minimum wall time of each over REPS repetitions (which of the two
// goes first alternates) and the overhead of each; on a shared machine the
// minimum is the steadier figure.
// Usage: campaign_bench IMAGE [REPS] [ROWS]
//   ROWS: use only the first ROWS rows of IMAGE (a fast simulation, so that
//   the campaign's fixed cost per setting shows: journal line, fsync, row).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/simulate.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU time of the whole process (all threads), in seconds.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: campaign_bench IMAGE [REPS] [ROWS]\n");
    return 2;
  }
  const int reps = argc > 2 ? std::atoi(argv[2]) : 3;
  std::string image_path = argv[1];
  if (argc > 3) {
    const fss::Image full = fss::read_png(image_path);
    fss::Image top(full.width, std::min(std::atoi(argv[3]), full.height), full.channels);
    for (int c = 0; c < top.channels; ++c) {
      for (int y = 0; y < top.height; ++y) {
        std::copy(full.row(c, y), full.row(c, y) + full.width, top.row(c, y));
      }
    }
    image_path = (std::filesystem::temp_directory_path() / "fssim_campaign_bench.png").string();
    const std::vector<std::uint8_t> png = fss::encode_png8(top);
    std::ofstream(image_path, std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  }
  fss::CampaignSpec spec;
  spec.inputs = {image_path};
  spec.codes = {"snapshot", "raskar", "mip", "sinc"};
  spec.velocity = "0.5,1";
  spec.snr = "50,100";
  spec.trials = 2;
  const fss::ResolvedCampaign campaign = fss::resolve_campaign(spec);
  const auto dir = std::filesystem::temp_directory_path() / "fssim_campaign_bench";
  std::vector<double> with_campaign, one_by_one, campaign_cpu, one_by_one_cpu;
  double checksum = 0.0;
  long long plans_built = 0, plans_reused = 0;
  const auto run_campaign = [&] {
    std::filesystem::remove_all(dir);
    const auto start = std::chrono::steady_clock::now();
    const double cpu = cpu_seconds();
    const fss::CampaignRunSummary summary = fss::RunCampaign(campaign, dir.string(), {});
    plans_built = summary.plans_built;
    plans_reused = summary.plans_reused;
    campaign_cpu.push_back(cpu_seconds() - cpu);
    with_campaign.push_back(seconds_since(start));
  };
  const auto run_one_by_one = [&] {
    const auto start = std::chrono::steady_clock::now();
    const double cpu = cpu_seconds();
    const fss::Image image = fss::read_png(image_path);
    for (long long i = 0; i < campaign.setting_count(); ++i) {
      const fss::Setting s = fss::setting_at(campaign, i);
      const fss::SimulationReport report =
          fss::Simulate(fss::setting_options(campaign, s), image, campaign.codes[s.code].code);
      checksum += report.trials.rmse_mean;
    }
    one_by_one_cpu.push_back(cpu_seconds() - cpu);
    one_by_one.push_back(seconds_since(start));
  };
  for (int r = 0; r < reps; ++r) {
    if (r % 2 == 0) {
      run_campaign();
      run_one_by_one();
    } else {
      run_one_by_one();
      run_campaign();
    }
  }
  std::filesystem::remove_all(dir);
  const double c = median(with_campaign), o = median(one_by_one);
  const double c_min = *std::min_element(with_campaign.begin(), with_campaign.end());
  const double o_min = *std::min_element(one_by_one.begin(), one_by_one.end());
  std::printf("campaign_bench: %lld settings x %d trials on %s, %d repetitions\n",
              campaign.setting_count(), spec.trials, image_path.c_str(), reps);
  std::printf("  kernels: %lld computed, %lld reused by the campaign\n", plans_built, plans_reused);
  std::printf("                        median     min\n");
  std::printf("  fss::RunCampaign      %.3f s   %.3f s\n", c, c_min);
  std::printf("  Simulate one by one   %.3f s   %.3f s\n", o, o_min);
  const double cc = median(campaign_cpu), oc = median(one_by_one_cpu);
  std::printf("  CPU time, median      %.3f s against %.3f s: %+.2f %%\n", cc, oc,
              100.0 * (cc - oc) / oc);
  std::printf("  per setting           %+.2f ms  %+.2f ms\n",
              1e3 * (c - o) / static_cast<double>(campaign.setting_count()),
              1e3 * (c_min - o_min) / static_cast<double>(campaign.setting_count()));
  std::printf("  overhead              %+.2f %%   %+.2f %%   (checksum %.6f)\n",
              100.0 * (c - o) / o, 100.0 * (c_min - o_min) / o_min, checksum);
  return 0;
}
