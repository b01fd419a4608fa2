// Micro-benchmarks: the photon-noise sampler against the scalar Box-Muller
// baseline, and one batch of row FFTs.
#include <benchmark/benchmark.h>

#include <complex>
#include <vector>

#include "fss/core/fft.h"
#include "fss/model/noise.h"

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
BENCHMARK(BM_RowFFTBatch)->Arg(512)->Arg(920)->Arg(4000)->Arg(7896);

}  // namespace

BENCHMARK_MAIN();
