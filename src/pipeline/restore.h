// Crops, mirror extension and inverse filtering (docs/method.md §4), one row
// at a time. Conventions: image.h.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "core/fft.h"
#include "fss/core/image.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/geometry.h"
#include "pipeline/restoration_filter.h"

namespace fss {

// Restoration of one row at a time, the last stage of Simulate's row
// pipeline: observed crop [h, h + Wa), mirror extension to N = 2 Wa, inverse
// filter r = IDFT_N(DFT_N(mirror) / K), output columns [2h, 2h + Wo).
//
// The inverse filter is the circular convolution of the mirror row with the
// filter's impulse response on the N-point grid. Since the mirror row is the
// crop and its reverse, the Wo output columns are two linear convolutions of
// the crop alone, one with the crop reversed, which one transform pair of a
// length M >= Wa + Wo - 1 < N computes (restore.cpp, folded_filters). M is
// chosen fast for FFTW (2^a m, m in {1, 3, 5, 7, 9, 15}), while N = 2 (W - B)
// is set by the image width and often has a large prime factor, which makes
// its transforms several times slower (CONTRIBUTING.md, "Hand-written fast
// paths").
// The folded convolution's round-off is spread over every frequency, so a K
// near a zero (sup |1/K| |K(0)| above 1e6) keeps the grid, where each bin's
// round-off stays its own. Both compute the same operator and differ by
// round-off only (1e-13 of the values, tested). transform_length() says which
// length a restorer uses.
// 1 / K on the n-point grid, 0 at the bins where K vanishes, as the
// restoration takes it; the number of those bins in *zero_bins.
std::vector<Complex> inverse_transfer_bins(std::span<const double> gains, double velocity,
                                           double dt, int n, int* zero_bins);

class RowRestorer {
 public:
  // The inverse filter 1 / K of the code at `velocity`.
  RowRestorer(const Geometry& geometry, std::span<const double> gains, double velocity, double dt);
  // Any filter H on the N grid (restoration_filter.h) in place of 1 / K.
  RowRestorer(const Geometry& geometry, FilterBins filter);

  // Buffers of one worker thread.
  class Scratch {
   public:
    explicit Scratch(const RowRestorer& restorer) : workspace(restorer.fft_.size()) {}

   private:
    friend class RowRestorer;
    RowFFT::Workspace workspace;
  };

  // restored[0 .. Wo) from observation[0 .. W).
  void restore(const double* observation, Scratch& scratch, double* restored) const;
  // The same from the observed crop alone, crop[0 .. Wa) (observation column h + j).
  void restore_crop(const double* crop, Scratch& scratch, double* restored) const;
  int zero_bins() const { return zero_bins_; }
  // M of the folded convolution, or N = 2 Wa.
  int transform_length() const { return fft_.size(); }
  // The memory of the filters it holds.
  std::size_t bytes() const;

 private:
  Geometry geometry_;
  // Declared before inverse_, whose initializer counts the zero bins into it.
  int zero_bins_ = 0;
  std::vector<std::complex<double>> inverse_;  // H (1 / K) on the N grid, 0 where K vanishes
  const RowFFT& fft_;                          // length M or N
  // The folded convolution's filters GA / M and GB' / M (empty on the grid).
  std::vector<std::complex<double>> direct_filter_;
  std::vector<std::complex<double>> reversed_filter_;
};

// The impulse response of the inverse filter on the n-point grid, h =
// IDFT_n(1 / K) with 1 / K taken as 0 where K vanishes (transfer_vanishes,
// model/kernel.h; as the restoration does):
// the inverse filter applied to a unit impulse at 0, whose DFT is 1 at every
// bin. Row column x of the filtered mirror row m is sum_j m[j] h[(x - j) mod n].
std::vector<double> inverse_filter_impulse_response(std::span<const double> gains, double velocity,
                                                    double dt, int n);

// The length the folded convolution of a well-conditioned K transforms for a
// geometry (RowRestorer::transform_length): the smallest 2^a m >= Wa + Wo - 1,
// a >= 1 and m in {1, 3, 5, 7, 9, 15}.
int restoration_transform_length(const Geometry& geometry);

}  // namespace fss
