// Whole-image versions of the observation and the restoration, for the tests
// only: they check the row pipeline (RowObserver, RowRestorer) against the
// definitions of docs/method.md §2-§4 written image by image. Conventions:
// image.h.
#pragma once

#include <complex>
#include <cstdint>
#include <span>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "pipeline/observe.h"

namespace fss {

// The observation's parameters and what the whole-image paths add: the seed
// of the noise streams and the worker threads (0: all).
struct ReferenceParams : ObservationParams {
  std::uint64_t seed = 0;
  int threads = 0;
};

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

// e = rowconv(u, K) = IDFT(DFT(u) K), row by row, circular: the ideal
// observation of both modes.
Image convolve_rows(const RowSpectra& u, std::span<const double> gains,
                    const ReferenceParams& params);

// The expectation of the noisy observation, E[o]: PoissonSNR(e) has mean
// max(e, 0), so this is max(rowconv(u, K), 0) (analog) or
// sum_k alpha_k max(rowconv(u, K_k), 0) (numerical). The clip matters where
// the band-limited interpolation of the image rings below 0 near dark edges;
// it is what the reference program's run at a huge SNR converges to.
Image observe_noise_free(const RowSpectra& u, std::span<const double> gains, ShutterMode mode,
                         const ReferenceParams& params);

// Analog flutter shutter: o = PoissonSNR(rowconv(u, K)). Gains must lie in [0, 1].
Image observe_analog(const RowSpectra& u, std::span<const double> gains,
                     const ReferenceParams& params);

// Numerical flutter shutter: o = sum_k alpha_k PoissonSNR(rowconv(u, K_k)),
// one elementary exposure per slot, streamed into one accumulator (memory
// O(W H)). Slots with alpha_k = 0 contribute nothing and are skipped.
Image observe_numerical(const RowSpectra& u, std::span<const double> gains,
                        const ReferenceParams& params);

// Row of width 2 Wa: column j is crop column j for j < Wa, 2 Wa - 1 - j after.
Image mirror_extend(const Image& crop);

struct Deconvolution {
  Image image;        // IDFT(DFT(mirror) / K), same size as the input
  int zero_bins = 0;  // bins where K vanishes (transfer_vanishes); they are set to 0
};
// Plain inverse filter, K evaluated on the mirror's own width.
Deconvolution inverse_filter(const Image& mirrored, std::span<const double> gains, double velocity,
                             double dt, int threads);

// The three aligned outputs, Wo wide: restored = deconvolved column c + 2h,
// observed = observation column c + 3h, ground truth = input column c + 3h.
struct Restoration {
  Image restored;
  Image observed;  // not yet divided by K(0)
  Image groundtruth;
  int zero_bins = 0;
};
Restoration restore(const Image& observation, const Image& input, const Geometry& geometry,
                    std::span<const double> gains, double velocity, double dt, int threads);

}  // namespace fss
