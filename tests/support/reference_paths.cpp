// Whole-image reference paths of the observation and the restoration
// (reference_paths.h), for the tests.
#include "support/reference_paths.h"

#include <algorithm>
#include <cmath>

#include "core/fft.h"
#include "core/parallel.h"
#include "fss/model/kernel.h"
#include "fss/model/transfer.h"
#include "pipeline/restore.h"

namespace fss {

RowSpectra row_spectra(const Image& image, int threads) {
  RowSpectra spectra;
  spectra.width = image.width;
  spectra.height = image.height;
  spectra.channels = image.channels;
  const int bins = spectra.spectrum_size();
  const int rows = image.channels * image.height;
  spectra.bins.resize(static_cast<std::size_t>(rows) * bins);
  const RowFFT& fft = RowFFT::for_size(image.width);
  parallel_for(rows, threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(image.width);
    for (int r = begin; r < end; ++r) {
      const double* src = image.data.data() + static_cast<std::size_t>(r) * image.width;
      std::copy(src, src + image.width, workspace.real().begin());
      fft.forward(workspace);
      std::copy(workspace.spectrum().begin(), workspace.spectrum().end(),
                spectra.bins.begin() + static_cast<std::ptrdiff_t>(r) * bins);
    }
  });
  return spectra;
}

namespace {

// The observation of every row of u, from its stored spectra.
Image observe_all(const RowSpectra& u, std::span<const double> gains, ShutterMode mode, bool noisy,
                  const ReferenceParams& params) {
  const RowObserver observer(u.width, gains, mode, params);
  Image out(u.width, u.height, u.channels);
  parallel_for(u.channels * u.height, params.threads, [&](int begin, int end) {
    RowObserver::Scratch scratch(observer);
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      observer.load_spectrum(u.row(c, y), scratch);
      observer.observe(noisy, params.seed, c, y, scratch,
                       std::span<double>(out.row(c, y), static_cast<std::size_t>(u.width)));
    }
  });
  return out;
}

}  // namespace

Image convolve_rows(const RowSpectra& u, std::span<const double> gains,
                    const ReferenceParams& params) {
  Image out(u.width, u.height, u.channels);
  const RowFFT& fft = RowFFT::for_size(u.width);
  const auto filter = transfer_function_bins(gains, params.velocity, params.dt, u.width);
  const int bins = u.spectrum_size();
  parallel_for(u.channels * u.height, params.threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(u.width);
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      std::copy(u.row(c, y), u.row(c, y) + bins, workspace.spectrum().begin());
      fft.inverse_filtered(workspace, filter);  // e = IDFT(DFT(u) K)
      std::copy(workspace.real().begin(), workspace.real().end(), out.row(c, y));
    }
  });
  return out;
}

Image observe_noise_free(const RowSpectra& u, std::span<const double> gains, ShutterMode mode,
                         const ReferenceParams& params) {
  return observe_all(u, gains, mode, false, params);
}

Image observe_analog(const RowSpectra& u, std::span<const double> gains,
                     const ReferenceParams& params) {
  return observe_all(u, gains, ShutterMode::kAnalog, true, params);
}

Image observe_numerical(const RowSpectra& u, std::span<const double> gains,
                        const ReferenceParams& params) {
  return observe_all(u, gains, ShutterMode::kNumerical, true, params);
}

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
      fft.forward(workspace);
      fft.inverse_filtered(workspace, inverse);  // IDFT(DFT(row) / K)
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
