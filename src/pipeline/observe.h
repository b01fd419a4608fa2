// The flutter shutter observation (docs/method.md §2, §3), one row at a
// time. Conventions: image.h.
#pragma once

#include <complex>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/fft.h"
#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"
#include "model/noise.h"

namespace fss {

struct ObservationParams {
  double velocity = 1.0;  // pixels per time slot, signed
  double dt = 1.0;        // time slot length
  double snr = 100.0;     // SNR of a level-100 landscape seen through one slot
  // Numerical mode: each pixel's normal-branch frames drawn as one normal
  // (AggregatedRowSampler, docs/method.md §6c) instead of one by one.
  bool aggregate_noise = false;
  // The sensor (docs/method.md §10); a default one is the paper's photon
  // noise, every output bit unchanged.
  SensorModel sensor;
  // Columns [first, end) of the row whose readouts the noise-free pass
  // checks for clipping (ReadoutClipping); end -1: the whole row.
  int clipping_first_column = 0;
  int clipping_end_column = -1;
};

// Readouts of a noise-free pass whose mean charge (photo plus dark electrons)
// a nonlinear sensor clips, where the exact prediction's linear model does
// not hold (docs/method.md §10): `saturated` reach min(F, (2^b - 1) G), the
// full well or the ADC's top; `near_zero` (ADC only) lie within 3 standard
// deviations of 0, sqrt(charge + sigma_r^2), where the ADC clips negative
// readouts. Counted only for a sensor with a full well or an ADC.
struct ReadoutClipping {
  std::uint64_t saturated = 0;
  std::uint64_t near_zero = 0;
  ReadoutClipping& operator+=(const ReadoutClipping& other) {
    saturated += other.saturated;
    near_zero += other.near_zero;
    return *this;
  }
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
    std::vector<double> doubled;  // e_0 twice: its shifts are windows of it, integer v dt only
    // The per-frame sampler's intensities of e_0 and their square roots,
    // twice over like `doubled` (integer v dt), made at the row's first
    // noisy slot.
    std::vector<double> lambda;
    std::vector<double> root;
    std::size_t knuth_pixels = 0;
    // The aggregated sampler's, likewise.
    AggregatedRowSampler::IntensityRows frame_intensities;
    std::size_t normal_pixels = 0;
    bool intensities_ready = false;
    std::vector<double> unit_variance;        // Var(PoissonSNR(e_0)), integer v dt only
    std::vector<double> exact_unit_variance;  // the same without the rounding term
    PoissonRowSampler sampler;
    AggregatedRowSampler aggregated;
  };

  int width() const { return width_; }

  // This observer with the snr, noise model, sensor and clipping columns of
  // `params` (its velocity and dt must be this observer's): the filters (the
  // part that costs) are shared, not computed again (SimulationPlan, simulate.h).
  RowObserver with_noise(const ObservationParams& params) const;

  // Loads the row to observe into the scratch: a real row (width values),
  // transformed here, or its DFT (width / 2 + 1 bins) when already known.
  void load_row(const double* row, Scratch& scratch) const;
  void load_spectrum(const std::complex<double>* bins, Scratch& scratch) const;

  // Where observe() writes the row last loaded into the scratch; each span is
  // empty (not wanted) or holds width values:
  //   noisy        the observation o (PoissonSNR, streams of (seed, channel,
  //                slot k or 0, row); aggregated: AggregatedRowSampler's),
  //   expectation  its expectation E[o] (docs/method.md §2, §3, §6c),
  //   variance     each pixel's Var(o) (docs/method.md §6b), with the
  //                expectation only: numerical sum_k alpha_k^2
  //                Var(PoissonSNR(e_k)), analog Var(PoissonSNR(e)), Var as
  //                poisson_snr_variance (noise.h), without its rounding
  //                term for the frames aggregated noise draws exactly
  //                (grouped frames, docs/method.md §6c).
  // Asking for both the noisy observation and its expectation computes each
  // exposure e_k once for both: the first trial of a noisy run and its
  // noise-free pass share the row's transforms. Each output gets the same
  // bits as when it is asked for alone.
  struct Outputs {
    std::span<double> noisy;
    std::span<double> expectation;
    std::span<double> variance;
  };

  // Observes the row last loaded into `scratch` into `outputs`.
  // With an enabled sensor (docs/method.md §10) each readout (a frame, or the
  // analog exposure) is read as SensorReadout::read; the expectation is
  // max(e, 0) for a linear sensor, and, with a full well or an ADC, the mean
  // charge clipped, (min(max(e, 0) lambda2 + dark, clip) - dark) / lambda2,
  // without the ADC's rounding (counted as variance G^2 / 12); the variance
  // adds readout_variance_electrons2 / lambda2^2 per readout, and the dark
  // charge moves the Poisson's branch test to lambda + dark >= 50. Returns the
  // readouts the expectation finds clipped (zero without an expectation).
  ReadoutClipping observe(std::uint64_t seed, int channel, int row, Scratch& scratch,
                          const Outputs& outputs) const;
  // out = the noisy observation (`noisy`) or its expectation, with Var(o)
  // into `variance` for the expectation when it is not empty.
  ReadoutClipping observe(bool noisy, std::uint64_t seed, int channel, int row, Scratch& scratch,
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
  // The noise part of the state: snr, sensor readouts, clipping columns.
  void set_noise(const ObservationParams& params);
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
  // The noisy part of slot k's readout of e_k (numerical mode): the sampler
  // of the noise model adds it to `noisy` (aggregated: its normal-branch part
  // is finished by observe()).
  void add_noisy_slot(std::size_t k, std::span<const double> e, const SlotShift& shift,
                      std::uint64_t seed, std::uint64_t channel, std::uint64_t row,
                      Scratch& scratch, std::span<double> noisy) const;
  // out += E[o] of one readout of gain alpha: alpha max(e, 0) (linear
  // sensor), else the clipped mean charge, counting clipped readouts.
  void add_expectation(std::span<const double> e, double alpha, double lambda2,
                       std::span<double> out, ReadoutClipping& clipping) const;

  int width_;
  std::vector<double> gains_;
  ShutterMode mode_;
  double snr_;
  const RowFFT& fft_;
  bool aggregate_ = false;   // numerical mode with aggregated noise
  std::vector<int> groups_;  // gain_groups(gains_): the frames aggregated noise draws exactly
  bool shift_ = false;       // numerical mode with an integer v dt
  long long step_ = 0;       // v dt when shift_
  // analog: {K}; numerical: {K_0} when shift_, else K_k for each slot (empty when
  // alpha_k = 0); shared by the copies of with_noise.
  std::shared_ptr<const std::vector<std::vector<std::complex<double>>>> filters_;
  bool sensor_ = false;        // the sensor is enabled
  bool sensor_linear_ = true;  // and has neither a full well nor an ADC
  SensorReadout readout_;      // of one readout of this mode
  // Numerical mode, per-frame sampler, linear sensor: the frames are read
  // without read noise (frame_readout_) and the read noise of all frames is
  // one normal per pixel of deviation sigma_r sqrt(sum_k alpha_k^2), the
  // same distribution (a sum of independent normals), one draw instead of L.
  bool sum_read_noise_ = false;
  SensorReadout frame_readout_;
  double summed_read_sd_ = 0.0;    // sigma_r sqrt(sum_k alpha_k^2), electrons
  double readout_variance_ = 0.0;  // readout_variance_electrons2, electrons^2
  int clipping_first_ = 0;
  int clipping_end_ = 0;
};

}  // namespace fss
