#include "fss/pipeline/restore.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fss/core/error.h"
#include "fss/core/fft.h"
#include "fss/core/parallel.h"
#include "fss/model/transfer.h"
#include "pipeline/reference_paths.h"

namespace fss {

namespace {
// 1 / K on the n-point grid; bins where K = 0 carry no information and are
// zeroed (counted in *zero_bins).
std::vector<Complex> inverse_transfer_bins(std::span<const double> gains, double velocity,
                                           double dt, int n, int* zero_bins) {
  std::vector<Complex> inverse = transfer_function_bins(gains, velocity, dt, n);
  *zero_bins = 0;
  for (Complex& k : inverse) {
    if (k == Complex(0.0)) {
      ++*zero_bins;
    } else {
      k = 1.0 / k;
    }
  }
  return inverse;
}

// r = IDFT(DFT(row) / K), in place in workspace.real().
void inverse_filter_row(const RowFFT& fft, const std::vector<Complex>& inverse,
                        RowFFT::Workspace& workspace) {
  fft.forward(workspace);
  fft.inverse_filtered(workspace, inverse);
}
}  // namespace

RowRestorer::RowRestorer(const Geometry& geometry, std::span<const double> gains, double velocity,
                         double dt)
    : geometry_(geometry),
      fft_(RowFFT::for_size(geometry.mirror_width)),
      inverse_(inverse_transfer_bins(gains, velocity, dt, geometry.mirror_width, &zero_bins_)) {}

void RowRestorer::restore(const double* observation, Scratch& scratch, double* restored) const {
  const int wa = geometry_.observed_width;
  const double* crop = observation + geometry_.half_blur;  // observed crop [h, h + Wa)
  double* mirror = scratch.workspace.real().data();
  std::copy(crop, crop + wa, mirror);
  std::reverse_copy(crop, crop + wa, mirror + wa);  // column j >= Wa is 2 Wa - 1 - j
  inverse_filter_row(fft_, inverse_, scratch.workspace);
  const double* deconvolved = scratch.workspace.real().data() + 2 * geometry_.half_blur;
  std::copy(deconvolved, deconvolved + geometry_.output_width, restored);
}

// ---------------------------------------------------------------------------
// Whole-image reference paths, for the tests (reference_paths.h).

Image mirror_extend(const Image& crop) {
  const int wa = crop.width;
  Image out(2 * wa, crop.height, crop.channels);
  for (int c = 0; c < crop.channels; ++c) {
    for (int y = 0; y < crop.height; ++y) {
      const double* src = crop.row(c, y);
      double* dst = out.row(c, y);
      std::copy(src, src + wa, dst);
      std::reverse_copy(src, src + wa, dst + wa);  // column j >= Wa is 2 Wa - 1 - j
    }
  }
  return out;
}

Deconvolution inverse_filter(const Image& mirrored, std::span<const double> gains, double velocity,
                             double dt, int threads) {
  const int n = mirrored.width;
  Deconvolution result;
  const std::vector<Complex> inverse =
      inverse_transfer_bins(gains, velocity, dt, n, &result.zero_bins);
  result.image = Image(n, mirrored.height, mirrored.channels);
  const RowFFT& fft = RowFFT::for_size(n);
  parallel_for(mirrored.channels * mirrored.height, threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(n);
    for (int r = begin; r < end; ++r) {
      const double* src = mirrored.data.data() + static_cast<std::size_t>(r) * n;
      std::copy(src, src + n, workspace.real().begin());
      inverse_filter_row(fft, inverse, workspace);
      std::copy(workspace.real().begin(), workspace.real().end(),
                result.image.data.data() + static_cast<std::size_t>(r) * n);
    }
  });
  return result;
}

Restoration restore(const Image& observation, const Image& input, const Geometry& geometry,
                    std::span<const double> gains, double velocity, double dt, int threads) {
  const int h = geometry.half_blur;
  const RowRestorer restorer(geometry, gains, velocity, dt);
  Restoration out;
  out.restored = Image(geometry.output_width, observation.height, observation.channels);
  parallel_for(observation.channels * observation.height, threads, [&](int begin, int end) {
    RowRestorer::Scratch scratch(restorer);
    for (int r = begin; r < end; ++r) {
      const int c = r / observation.height;
      const int y = r % observation.height;
      restorer.restore(observation.row(c, y), scratch, out.restored.row(c, y));
    }
  });
  out.observed = crop_columns(observation, 3 * h, geometry.output_width);
  out.groundtruth = crop_columns(input, 3 * h, geometry.output_width);
  out.zero_bins = restorer.zero_bins();
  return out;
}

}  // namespace fss
