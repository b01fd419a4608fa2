// Crops, mirror extension and inverse filtering (docs/method.md §4), one row
// at a time. Conventions: image.h.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "fss/core/fft.h"
#include "fss/core/image.h"
#include "fss/pipeline/geometry.h"

namespace fss {

// Restoration of one row at a time, the last stage of Simulate's row
// pipeline: observed crop [h, h + Wa), mirror
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
  // Declared before inverse_, whose initializer counts the zero bins into it.
  int zero_bins_ = 0;
  std::vector<std::complex<double>> inverse_;  // 1 / K on the 2 Wa grid, 0 where K = 0
};

}  // namespace fss
