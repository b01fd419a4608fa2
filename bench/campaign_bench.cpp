// Campaign overhead: the same simulations run by fss::RunCampaign (journal,
// fsync per setting, result files) and one by one with fss::Simulate in one
// process (image decoded once, codes loaded once). Prints the median wall
// time of each over REPS alternating repetitions and the overhead.
// Usage: campaign_bench IMAGE [REPS]   (bench/run.sh's build: build-bench/bench/)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/simulate.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: campaign_bench IMAGE [REPS]\n");
    return 2;
  }
  const int reps = argc > 2 ? std::atoi(argv[2]) : 3;
  fss::CampaignSpec spec;
  spec.inputs = {argv[1]};
  spec.codes = {"snapshot", "raskar", "mip", "sinc"};
  spec.velocity = "0.5,1";
  spec.snr = "50,100";
  spec.trials = 2;
  const fss::ResolvedCampaign campaign = fss::resolve_campaign(spec);
  const auto dir = std::filesystem::temp_directory_path() / "fssim_campaign_bench";
  std::vector<double> with_campaign, one_by_one;
  double checksum = 0.0;
  for (int r = 0; r < reps; ++r) {
    std::filesystem::remove_all(dir);
    auto start = std::chrono::steady_clock::now();
    fss::RunCampaign(campaign, dir.string(), {});
    with_campaign.push_back(seconds_since(start));

    start = std::chrono::steady_clock::now();
    const fss::Image image = fss::read_png(argv[1]);
    for (long long i = 0; i < campaign.setting_count(); ++i) {
      const fss::Setting s = fss::setting_at(campaign, i);
      const fss::SimulationReport report =
          fss::Simulate(fss::setting_options(campaign, s), image, campaign.codes[s.code].code);
      checksum += report.trials.rmse_mean;
    }
    one_by_one.push_back(seconds_since(start));
  }
  std::filesystem::remove_all(dir);
  const double c = median(with_campaign), o = median(one_by_one);
  std::printf("campaign_bench: %lld settings x %d trials on %s, median of %d\n",
              campaign.setting_count(), spec.trials, argv[1], reps);
  std::printf("  fss::RunCampaign      %.3f s\n  Simulate one by one   %.3f s\n", c, o);
  std::printf("  overhead              %+.2f %%   (checksum %.6f)\n", 100.0 * (c - o) / o,
              checksum);
  return 0;
}
