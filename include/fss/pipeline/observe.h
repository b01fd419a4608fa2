// The flutter shutter observation (docs/method.md §2, §3), one row at a
// time. Conventions: image.h.
#pragma once

#include <complex>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fss/core/fft.h"
#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/noise.h"

namespace fss {

struct ObservationParams {
  double velocity = 1.0;  // pixels per time slot, signed
  double dt = 1.0;        // time slot length
  double snr = 100.0;     // SNR of a level-100 landscape seen through one slot
  // Numerical mode: each pixel's normal-branch frames drawn as one normal
  // (AggregatedRowSampler, docs/method.md §6c) instead of one by one.
  bool aggregate_noise = false;
  // Used only by the whole-image reference paths (src/pipeline/reference_paths.h).
  std::uint64_t seed = 0;
  int threads = 0;
};

// The observation of one row at a time, from the row's DFT: the first stage
// of Simulate's row pipeline. In numerical mode the elementary exposures are streamed into the
// output row; when s = v dt is an integer they are exact circular shifts of
// each other (K_k = K_0 exp(-i xi s k)) and cost no transform.
class RowObserver {
 public:
  // Throws a usage fss::Error in analog mode for a gain outside [0, 1].
  RowObserver(int width, std::span<const double> gains, ShutterMode mode,
              const ObservationParams& params);

  // Buffers of one worker thread.
  class Scratch {
   public:
    explicit Scratch(const RowObserver& observer);

   private:
    friend class RowObserver;
    RowFFT::Workspace workspace;
    std::vector<std::complex<double>> spectrum;
    std::vector<double> shifted;
    std::vector<double> unit_variance;  // Var(PoissonSNR(e_0)), integer v dt only
    PoissonRowSampler sampler;
    AggregatedRowSampler aggregated;
  };

  int width() const { return width_; }

  // This observer with another snr and noise model: the filters (the part
  // that costs) are shared, not computed again (SimulationPlan, simulate.h).
  RowObserver with_noise(double snr, bool aggregate_noise) const;

  // Loads the row to observe into the scratch: a real row (width values),
  // transformed here, or its DFT (width / 2 + 1 bins) when already known.
  void load_row(const double* row, Scratch& scratch) const;
  void load_spectrum(const std::complex<double>* bins, Scratch& scratch) const;

  // out (width values) = the observation of the row last loaded into
  // `scratch`: noisy (PoissonSNR, streams of (seed, channel, slot k or 0,
  // row); aggregated: AggregatedRowSampler's) or, when `noisy` is false, its
  // expectation (docs/method.md §2, §3, §6c). With `noisy` false and a
  // `variance` row (width values), that row also receives each pixel's
  // variance of the noisy observation, Var(o) (docs/method.md §6b):
  // numerical sum_k alpha_k^2 Var(PoissonSNR(e_k)), analog Var(PoissonSNR(e)),
  // Var as poisson_snr_variance (noise.h).
  void observe(bool noisy, std::uint64_t seed, int channel, int row, Scratch& scratch,
               std::span<double> out, std::span<double> variance = {}) const;

  // Aggregated noise (numerical mode): the next noisy observe() with this
  // scratch also records the row's plan (AggregatedRowPlan, noise.h) into
  // `plan`, unless the row has more Knuth-branch pixel frames than its width
  // (then the plan stays unrecorded); replay() then gives that row's noisy
  // observation for any seed, the same bytes as observe(), without loading
  // or filtering the row.
  bool aggregates_noise() const { return aggregate_; }
  void record_plan(AggregatedRowPlan* plan, Scratch& scratch) const;
  void replay(const AggregatedRowPlan& plan, std::uint64_t seed, int channel, int row,
              Scratch& scratch, std::span<double> out) const;

 private:
  // e = IDFT(spectrum * filter) / width into scratch.workspace.real().
  std::span<const double> filtered(const std::vector<std::complex<double>>& filter,
                                   Scratch& scratch) const;
  // With an integer v dt, slot k's exposure is e_0 shifted by `offset`
  // columns; `e0` is empty otherwise.
  struct SlotShift {
    std::span<const double> e0;
    std::size_t offset = 0;
  };
  // per_slot(k, e_k, shift) for each slot k with a nonzero gain, in k order,
  // e_k from the row last loaded into `scratch` (numerical mode).
  template <typename PerSlot>
  void for_each_slot(Scratch& scratch, const PerSlot& per_slot) const;

  int width_;
  std::vector<double> gains_;
  ShutterMode mode_;
  double snr_;
  const RowFFT& fft_;
  bool aggregate_ = false;  // numerical mode with aggregated noise
  bool shift_ = false;      // numerical mode with an integer v dt
  long long step_ = 0;      // v dt when shift_
  // analog: {K}; numerical: {K_0} when shift_, else K_k for each slot (empty when
  // alpha_k = 0); shared by the copies of with_noise.
  std::shared_ptr<const std::vector<std::vector<std::complex<double>>>> filters_;
};

}  // namespace fss
