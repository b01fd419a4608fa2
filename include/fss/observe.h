// The flutter shutter observation (SPEC 2, 3). Conventions: image.h.
#pragma once

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "fss/code.h"
#include "fss/image.h"

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
