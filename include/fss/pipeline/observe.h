// The flutter shutter observation (SPEC 2, 3). Conventions: image.h.
#pragma once

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "fss/model/code.h"
#include "fss/core/fft.h"
#include "fss/core/image.h"
#include "fss/model/noise.h"

namespace fss {

// The DFT of every row of an image (channel-major, then row), computed once
// and shared by every observation of that image.
struct RowSpectra {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::complex<double>> bins;  // (c * height + y) * (width / 2 + 1) + i

  int spectrum_size() const { return width / 2 + 1; }
  const std::complex<double>* row(int c, int y) const {
    return bins.data() + (static_cast<std::size_t>(c) * height + y) * spectrum_size();
  }
};
RowSpectra row_spectra(const Image& image, int threads);

struct ObservationParams {
  double velocity = 1.0;  // pixels per time slot, signed
  double dt = 1.0;        // time slot length
  double snr = 100.0;     // SNR of a level-100 landscape seen through one slot
  std::uint64_t seed = 0;
  int threads = 0;
};

// The observation of one row at a time, from the row's DFT: the building
// block of the image-level functions below and of Simulate's row-streamed
// pipeline. In numerical mode the elementary exposures are streamed into the
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
    PoissonRowSampler sampler;
  };

  int width() const { return width_; }

  // Loads the row to observe into the scratch: a real row (width values),
  // transformed here, or its DFT (width / 2 + 1 bins) when already known.
  void load_row(const double* row, Scratch& scratch) const;
  void load_spectrum(const std::complex<double>* bins, Scratch& scratch) const;

  // out (width values) = the observation of the row last loaded into
  // `scratch`: noisy (PoissonSNR, streams of (seed, channel, slot k or 0,
  // row)) or, when `noisy` is false, its expectation (SPEC 2, 3).
  void observe(bool noisy, std::uint64_t seed, int channel, int row, Scratch& scratch,
               std::span<double> out) const;

 private:
  // e = IDFT(spectrum * filter) / width into scratch.workspace.real().
  std::span<const double> filtered(const std::vector<std::complex<double>>& filter,
                                   Scratch& scratch) const;

  int width_;
  std::vector<double> gains_;
  ShutterMode mode_;
  double snr_;
  const RowFFT& fft_;
  bool shift_ = false;  // numerical mode with an integer v dt
  long long step_ = 0;  // v dt when shift_
  // analog: {K}; numerical: {K_0} when shift_, else K_k for each slot (empty when alpha_k = 0)
  std::vector<std::vector<std::complex<double>>> filters_;
};

// e = rowconv(u, K) = IDFT(DFT(u) K), row by row, circular: the ideal
// observation of both modes.
Image convolve_rows(const RowSpectra& u, std::span<const double> gains,
                    const ObservationParams& params);

// The expectation of the noisy observation, E[o]: PoissonSNR(e) has mean
// max(e, 0), so this is max(rowconv(u, K), 0) (analog) or
// sum_k alpha_k max(rowconv(u, K_k), 0) (numerical). The clip matters where
// the band-limited interpolation of the image rings below 0 near dark edges;
// it is what the reference program's run at a huge SNR converges to.
Image observe_noise_free(const RowSpectra& u, std::span<const double> gains, ShutterMode mode,
                         const ObservationParams& params);

// Analog flutter shutter: o = PoissonSNR(rowconv(u, K)). Gains must lie in [0, 1].
Image observe_analog(const RowSpectra& u, std::span<const double> gains,
                     const ObservationParams& params);

// Numerical flutter shutter: o = sum_k alpha_k PoissonSNR(rowconv(u, K_k)),
// one elementary exposure per slot, streamed into one accumulator (memory
// O(W H)). Slots with alpha_k = 0 contribute nothing and are skipped.
Image observe_numerical(const RowSpectra& u, std::span<const double> gains,
                        const ObservationParams& params);

}  // namespace fss
