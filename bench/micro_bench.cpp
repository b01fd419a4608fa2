// Micro-benchmarks: the photon-noise samplers against the floor of normal
// and Poisson generation (our xoshiro256** alone, a ziggurat normal, the C++
// library's normal_distribution and, when libgsl-dev is installed, GSL's
// ziggurat and Poisson), one batch of row FFTs, and RMSE_CI on real
// restorations. items_per_second counts variates (pixels for the row
// samplers: one normal-branch variate each; pixels of all channels for
// RMSE_CI).
#include <benchmark/benchmark.h>

#include <complex>
#include <map>
#include <random>
#include <vector>

#include "core/fft.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/simulate.h"
#include "model/exact_poisson.h"
#include "model/noise.h"
#include "pipeline/restore.h"
#include "synthetic_image.h"
#include "ziggurat.h"

#ifdef FSS_BENCH_HAVE_GSL
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#endif

// Google Benchmark's loop idiom `for (auto _ : state)` never reads `_`.
// NOLINTBEGIN(clang-analyzer-deadcode.DeadStores)
namespace {

// A row of expected photon counts typical of a 0..255 image at snr 100.
std::vector<double> test_row(int width) {
  std::vector<double> e(static_cast<std::size_t>(width));
  for (int x = 0; x < width; ++x) e[x] = 20.0 + (x * 37 % 230);
  return e;
}

// The scalar path: one PoissonSNR call per pixel, Box-Muller one variate at a time.
void BM_ScalarPoissonSNR(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  const fss::PoissonSNR noise(100.0);
  std::uint64_t row = 0;
  double sink = 0.0;
  for (auto _ : state) {
    fss::RandomStream stream(1, 0, 0, row++);
    for (int x = 0; x < width; ++x) sink += noise(e[x], stream);
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * width);
}
BENCHMARK(BM_ScalarPoissonSNR)->Arg(512)->Arg(4000);

// The batched, vectorized row sampler used by the simulator.
void BM_PoissonRowSampler(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  std::vector<double> out(static_cast<std::size_t>(width), 0.0);
  fss::PoissonRowSampler sampler(100.0);
  std::uint64_t row = 0;
  for (auto _ : state) {
    sampler.accumulate(e, {1, 0, 0, row++}, 1.0, out);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * width);
}
BENCHMARK(BM_PoissonRowSampler)->Arg(512)->Arg(4000);

// The aggregated sampler's cost per frame and pixel: L = 52 frames of the
// row summed into one normal per pixel (add_frame 52 times, finish once).
void BM_AggregatedRowSampler(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  std::vector<double> out(static_cast<std::size_t>(width), 0.0);
  fss::AggregatedRowSampler sampler(100.0);
  std::uint64_t row = 0;
  constexpr std::uint64_t kFrames = 52;
  for (auto _ : state) {
    for (std::uint64_t k = 0; k < kFrames; ++k) sampler.add_frame(e, {1, 0, k, row}, 1.0, out);
    sampler.finish({1, 0, 0, row++}, out);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * width * static_cast<std::int64_t>(kFrames));
}
BENCHMARK(BM_AggregatedRowSampler)->Arg(512)->Arg(4000);

// A row of 4000 pixels at snr 100 (lambda2 = 100) seen through 52 frames of
// gain 1, per frame and pixel: range(0) 0 the test row, 1 a dark row (e =
// 0.05, every frame on Knuth's branch). range(1): 0 the per-frame sampler
// (PoissonRowSampler, 52 rows), 1 the aggregated sampler without groups
// (every frame a single frame, as for a code of unique gains), 2 the
// aggregated sampler with the 52 frames as one group (one exact Poisson
// variate per pixel, as for raskar).
void BM_FramesOfOneGain(benchmark::State& state) {
  constexpr int kWidth = 4000;
  constexpr std::uint64_t kFrames = 52;
  std::vector<double> e = test_row(kWidth);
  if (state.range(0) == 1) e.assign(e.size(), 0.05);
  std::vector<double> out(static_cast<std::size_t>(kWidth), 0.0);
  const std::vector<double> gains(kFrames, 1.0);
  const int sampler_kind = static_cast<int>(state.range(1));
  fss::PoissonRowSampler per_frame(100.0);
  fss::AggregatedRowSampler aggregated(
      100.0, sampler_kind == 2 ? std::span<const double>(gains) : std::span<const double>());
  std::uint64_t row = 0;
  for (auto _ : state) {
    for (std::uint64_t k = 0; k < kFrames; ++k) {
      if (sampler_kind == 0) {
        per_frame.accumulate(e, {1, 0, k, row}, 1.0, out);
      } else {
        aggregated.add_frame(e, {1, 0, k, row}, 1.0, out);
      }
    }
    if (sampler_kind != 0) aggregated.finish({1, 0, 0, row}, out);
    ++row;
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kWidth * static_cast<std::int64_t>(kFrames));
}
BENCHMARK(BM_FramesOfOneGain)->ArgsProduct({{0, 1}, {0, 1, 2}});

// The exact Poisson sampler alone (exact_poisson_variate) at mean range(0)
// / 10: inversion below 10, transformed rejection above.
void BM_ExactPoissonVariate(benchmark::State& state) {
  const double mean = static_cast<double>(state.range(0)) / 10.0;
  fss::RandomStream stream(1, 0, 0, 0, 5);
  double sink = 0.0;
  for (auto _ : state) {
    for (int i = 0; i < 1000; ++i) sink += fss::exact_poisson_variate(mean, stream);
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(BM_ExactPoissonVariate)->Arg(1)->Arg(50)->Arg(99)->Arg(100)->Arg(1000)->Arg(100000);

// The same through the row sampler, a row of 4000 pixels of mean range(0) /
// 10: range(1) 1 add_exact_poisson_row (PTRS's first tries and their slow
// tests vectorized), 0 add_exact_poisson_row_scalar (the same bits, the slow
// tests one by one).
void BM_ExactPoissonRow(benchmark::State& state) {
  const std::vector<double> mean(4000, static_cast<double>(state.range(0)) / 10.0);
  std::vector<double> out(mean.size(), 0.0);
  fss::RandomStream stream(1, 0, 0, 0, 5);
  const bool bulk = state.range(1) == 1;
  for (auto _ : state) {
    bulk ? fss::add_exact_poisson_row(mean, stream, 1.0, out)
         : fss::add_exact_poisson_row_scalar(mean, stream, 1.0, out);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 4000);
}
BENCHMARK(BM_ExactPoissonRow)->ArgsProduct({{1, 50, 99, 100, 1000, 100000, 10000000}, {0, 1}});

// The floor, 1: raw 64-bit outputs of xoshiro256** (one per pixel is what
// the per-frame sampler's Box-Muller consumes).
void BM_Xoshiro(benchmark::State& state) {
  fss::RandomStream stream(1, 0, 0, 0);
  std::uint64_t sink = 0;
  for (auto _ : state) sink ^= stream.next();
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Xoshiro);

// The floor, 2: a row of normals as the per-frame sampler draws them
// (uniforms from one stream, then the vectorized Box-Muller batch).
void BM_BoxMullerRow(benchmark::State& state) {
  const auto width = static_cast<std::size_t>(state.range(0));
  const std::size_t pairs = (width + 1) / 2;
  std::vector<double> u1(pairs), u2(pairs), z(2 * pairs);
  std::uint64_t row = 0;
  for (auto _ : state) {
    fss::RandomStream stream(1, 0, 0, row++);
    for (std::size_t j = 0; j < pairs; ++j) {
      u1[j] = stream.uniform_open_zero();
      u2[j] = stream.uniform();
    }
    fss::box_muller_batch(u1.data(), u2.data(), z.data(), pairs);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(width));
}
BENCHMARK(BM_BoxMullerRow)->Arg(512)->Arg(4000);

// The same generator as a bare state (bench/ziggurat.h): xoshiro256** alone,
// to compare with BM_Xoshiro.
void BM_InlineXoshiro(benchmark::State& state) {
  fss_bench::InlineXoshiro stream(fss::RandomStream(1, 0, 0, 0));
  std::uint64_t sink = 0;
  for (auto _ : state) sink ^= stream.next();
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InlineXoshiro);

// The floor, 3: our ziggurat normal (bench/ziggurat.h), a row at a time, on
// RandomStream (as the library would call it) and on the inline generator
// (the fastest normal we could build).
template <typename Generator>
void ziggurat_row(benchmark::State& state) {
  const auto width = static_cast<std::size_t>(state.range(0));
  const fss_bench::ZigguratNormal ziggurat;
  std::vector<double> z(width);
  std::uint64_t row = 0;
  for (auto _ : state) {
    Generator stream(fss::RandomStream(1, 0, 0, row++));
    for (double& value : z) value = ziggurat(stream);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(width));
}
void BM_ZigguratRow(benchmark::State& state) { ziggurat_row<fss::RandomStream>(state); }
void BM_ZigguratRowInline(benchmark::State& state) {
  ziggurat_row<fss_bench::InlineXoshiro>(state);
}
BENCHMARK(BM_ZigguratRow)->Arg(512)->Arg(4000);
BENCHMARK(BM_ZigguratRowInline)->Arg(512)->Arg(4000);

// The floor, 4: what a C++ user reaches for first.
void BM_StdNormalDistribution(benchmark::State& state) {
  std::mt19937_64 engine(1);
  std::normal_distribution<double> normal;
  double sink = 0.0;
  for (auto _ : state) sink += normal(engine);
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StdNormalDistribution);

// The floor, 5: the C++ library's Poisson at the test row's intensities.
void BM_StdPoissonRow(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  std::mt19937_64 engine(1);
  double sink = 0.0;
  for (auto _ : state) {
    for (int x = 0; x < width; ++x) {
      std::poisson_distribution<long> poisson(e[x] * 100.0);  // lambda2 = 100
      sink += static_cast<double>(poisson(engine));
    }
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * width);
}
BENCHMARK(BM_StdPoissonRow)->Arg(512);

#ifdef FSS_BENCH_HAVE_GSL
// The floor, 6: GSL's ziggurat normal and its Poisson (outside references),
// on GSL's fastest good generators.
void gsl_gaussian_ziggurat(benchmark::State& state, const gsl_rng_type* type) {
  gsl_rng* rng = gsl_rng_alloc(type);
  double sink = 0.0;
  for (auto _ : state) sink += gsl_ran_gaussian_ziggurat(rng, 1.0);
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
  gsl_rng_free(rng);
}
BENCHMARK_CAPTURE(gsl_gaussian_ziggurat, mt19937, gsl_rng_mt19937);
BENCHMARK_CAPTURE(gsl_gaussian_ziggurat, taus2, gsl_rng_taus2);

void BM_GslPoissonRow(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_taus2);
  double sink = 0.0;
  for (auto _ : state) {
    for (int x = 0; x < width; ++x) sink += gsl_ran_poisson(rng, e[x] * 100.0);  // lambda2 = 100
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * width);
  gsl_rng_free(rng);
}
BENCHMARK(BM_GslPoissonRow)->Arg(512);
#endif

// Scalar Box-Muller normals alone (the baseline of the batch below).
void BM_ScalarBoxMuller(benchmark::State& state) {
  fss::RandomStream stream(1, 0, 0, 0);
  double sink = 0.0;
  for (auto _ : state) sink += stream.standard_normal();
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ScalarBoxMuller);

void BM_BoxMullerBatch(benchmark::State& state) {
  const std::size_t pairs = 2048;
  std::vector<double> u1(pairs), u2(pairs), z(2 * pairs);
  fss::RandomStream stream(1, 0, 0, 0);
  for (std::size_t j = 0; j < pairs; ++j) {
    u1[j] = stream.uniform_open_zero();
    u2[j] = stream.uniform();
  }
  for (auto _ : state) {
    fss::box_muller_batch(u1.data(), u2.data(), z.data(), pairs);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 2 * pairs);
}
BENCHMARK(BM_BoxMullerBatch);

// One batch of row FFTs: 512 rows of length n, forward and inverse.
void BM_RowFFTBatch(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const fss::RowFFT& fft = fss::RowFFT::for_size(n);
  fss::RowFFT::Workspace workspace(n);
  for (int x = 0; x < n; ++x) workspace.real()[x] = x % 17;
  for (auto _ : state) {
    for (int row = 0; row < 512; ++row) {
      fft.forward(workspace);
      fft.inverse(workspace);
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * 512);
}
// The deconvolution grids N = 2 Wa of widths 512 and 4000 (920, 7896) and the
// folded convolution's lengths that replace them (896, 8192).
BENCHMARK(BM_RowFFTBatch)->Arg(512)->Arg(896)->Arg(920)->Arg(4000)->Arg(7896)->Arg(8192);

// The restoration of one row (raskar, v = 1): crop, folded convolution,
// output columns; items are rows.
void BM_RowRestorer(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> gains = fss::builtin_code("raskar")->gains;
  const fss::Geometry geometry = fss::Geometry::compute(width, 52, 1.0, 1.0);
  const fss::RowRestorer restorer(geometry, gains, 1.0, 1.0);
  fss::RowRestorer::Scratch scratch(restorer);
  const std::vector<double> observation = test_row(width);
  std::vector<double> restored(static_cast<std::size_t>(geometry.output_width));
  for (auto _ : state) {
    restorer.restore(observation.data(), scratch, restored.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel("transform length " + std::to_string(restorer.transform_length()));
}
BENCHMARK(BM_RowRestorer)->Arg(512)->Arg(4000);

// The per-frame sampler on intensities computed once (a row whose frames are
// shifts of one exposure, as the simulator draws them at integer v dt).
void BM_PoissonRowSamplerShifted(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const std::vector<double> e = test_row(width);
  std::vector<double> out(static_cast<std::size_t>(width), 0.0);
  fss::PoissonRowSampler sampler(100.0);
  std::vector<double> lambda;
  std::vector<double> root;
  const std::size_t knuth = sampler.intensities_of(e, 0.0, lambda, root);
  std::uint64_t row = 0;
  for (auto _ : state) {
    sampler.accumulate(fss::PoissonRowSampler::Intensities{lambda, root, knuth}, {1, 0, 0, row++},
                       1.0, out);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * width);
}
BENCHMARK(BM_PoissonRowSamplerShifted)->Arg(512)->Arg(4000);

// RMSE_CI as Simulate takes it: the ground truth (the input, 8-bit levels)
// against a noisy restoration (raskar code, v = 1, snr 100), over the run's
// RMSE_CI window. Case 0: camera.png (a 252 x 512 window, gray); case 1:
// the generated 4000 x 3000 RGB image of bench/run.sh (3740 x 3000, three
// channels; its restoration takes a few seconds, once).
struct RmseCiCase {
  fss::Image input;
  fss::SimulationReport report;
};

const RmseCiCase& rmse_ci_case(int which) {
  static std::map<int, RmseCiCase> cases;
  auto found = cases.find(which);
  if (found != cases.end()) return found->second;
  RmseCiCase c;
  if (which == 0) {
    c.input = fss::read_png(FSS_SOURCE_DIR "/data/camera.png");
  } else {
    c.input = fss::bench::synthetic_test_image(4000, 3000);
    for (double& v : c.input.data) v = fss::png8_sample(v);  // as read from its PNG
  }
  fss::SimulationOptions options;
  options.noise = fss::NoiseModel::kAggregated;
  c.report = fss::Simulate(options, c.input, *fss::builtin_code("raskar"));
  return cases.emplace(which, std::move(c)).first->second;
}

void BM_RmseContrastInvariant(benchmark::State& state) {
  const RmseCiCase& c = rmse_ci_case(static_cast<int>(state.range(0)));
  const int threads = static_cast<int>(state.range(1));
  const fss::SimulationReport& r = c.report;
  double sink = 0.0;
  for (auto _ : state) {
    sink += fss::rmse_contrast_invariant(c.input, r.output_first_column(), r.restored,
                                         r.rmse_ci_first, r.rmse_ci_end, threads);
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * (r.rmse_ci_end - r.rmse_ci_first) *
                          r.restored.height * r.restored.channels);
}
BENCHMARK(BM_RmseContrastInvariant)
    ->ArgNames({"case", "threads"})
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({1, 1})
    ->Args({1, 2})
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
// NOLINTEND(clang-analyzer-deadcode.DeadStores)

BENCHMARK_MAIN();
