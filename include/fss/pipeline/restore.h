// Crops, mirror extension and inverse filtering (SPEC 4). Conventions: image.h.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "fss/core/fft.h"
#include "fss/core/image.h"

namespace fss {

struct Geometry {
  int width = 0;           // W, input and observation width
  int blur_length = 0;     // B = max(L, ceil(|v| dt L))
  int half_blur = 0;       // h = floor(B / 2)
  int observed_width = 0;  // Wa = W - B, observed crop [h, h + Wa)
  int mirror_width = 0;    // 2 Wa, the deconvolution grid
  int output_width = 0;    // Wo = W - 3 B

  // Throws a usage fss::Error when the image is too narrow for any output.
  static Geometry compute(int width, int code_length, double velocity, double dt);
};

// Row of width 2 Wa: column j is crop column j for j < Wa, 2 Wa - 1 - j after.
Image mirror_extend(const Image& crop);

struct Deconvolution {
  Image image;        // IDFT(DFT(mirror) / K), same size as the input
  int zero_bins = 0;  // bins where K = 0 exactly; they are set to 0
};
// Plain inverse filter, K evaluated on the mirror's own width.
Deconvolution inverse_filter(const Image& mirrored, std::span<const double> gains, double velocity,
                             double dt, int threads);

// Restoration of one row at a time, the building block of restore() and of
// Simulate's row-streamed pipeline: observed crop [h, h + Wa), mirror
// extension to 2 Wa, inverse filter, output columns [2h, 2h + Wo).
class RowRestorer {
 public:
  RowRestorer(const Geometry& geometry, std::span<const double> gains, double velocity, double dt);

  // Buffers of one worker thread.
  class Scratch {
   public:
    explicit Scratch(const RowRestorer& restorer) : workspace(restorer.geometry_.mirror_width) {}

   private:
    friend class RowRestorer;
    RowFFT::Workspace workspace;
  };

  // restored[0 .. Wo) from observation[0 .. W).
  void restore(const double* observation, Scratch& scratch, double* restored) const;
  int zero_bins() const { return zero_bins_; }

 private:
  Geometry geometry_;
  const RowFFT& fft_;
  std::vector<std::complex<double>> inverse_;  // 1 / K on the 2 Wa grid, 0 where K = 0
  int zero_bins_ = 0;
};

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
