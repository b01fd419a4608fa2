#include "fss/observe.h"

#include <algorithm>
#include <string>

#include "fss/error.h"
#include "fss/fft.h"
#include "fss/noise.h"
#include "fss/parallel.h"
#include "fss/transfer.h"

namespace fss {

RowSpectra row_spectra(const Image& image, int threads) {
  RowSpectra spectra;
  spectra.width = image.width;
  spectra.height = image.height;
  spectra.channels = image.channels;
  const int bins = spectra.spectrum_size();
  const int rows = image.channels * image.height;
  spectra.bins.resize(static_cast<std::size_t>(rows) * bins);
  const RowFFT fft(image.width);
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

// For every row r = c * height + y: e = IDFT(U_r * filter), then
// sink(c, y, e) with e the real row already divided by the row length.
template <typename Sink>
void for_each_filtered_row(const RowSpectra& u, const std::vector<Complex>& filter,
                           const RowFFT& fft, int threads, const Sink& sink) {
  const int bins = u.spectrum_size();
  const double inverse_n = 1.0 / u.width;
  parallel_for(u.channels * u.height, threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(u.width);
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      std::copy(u.row(c, y), u.row(c, y) + bins, workspace.spectrum().begin());
      multiply_half_spectrum(workspace.spectrum(), filter, u.width);
      fft.inverse(workspace);
      for (double& value : workspace.real()) value *= inverse_n;
      sink(c, y, workspace.real());
    }
  });
}

}  // namespace

Image convolve_rows(const RowSpectra& u, std::span<const double> gains,
                    const ObservationParams& params) {
  Image out(u.width, u.height, u.channels);
  const RowFFT fft(u.width);
  const auto filter = transfer_function_bins(gains, params.velocity, params.dt, u.width);
  for_each_filtered_row(u, filter, fft, params.threads,
                        [&](int c, int y, std::span<const double> e) {
                          std::copy(e.begin(), e.end(), out.row(c, y));
                        });
  return out;
}

Image observe_noise_free(const RowSpectra& u, std::span<const double> gains, ShutterMode mode,
                         const ObservationParams& params) {
  if (mode == ShutterMode::kAnalog) {
    // E[o] = max(rowconv(u, K), 0)
    Image out = convolve_rows(u, gains, params);
    for (double& value : out.data) value = std::max(value, 0.0);
    return out;
  }
  Image out(u.width, u.height, u.channels);
  const RowFFT fft(u.width);
  for (std::size_t k = 0; k < gains.size(); ++k) {
    const double alpha = gains[k];
    if (alpha == 0.0) continue;
    const auto filter =
        slot_transfer_function_bins(static_cast<int>(k), params.velocity, params.dt, u.width);
    for_each_filtered_row(u, filter, fft, params.threads,
                          [&](int c, int y, std::span<const double> e) {
                            // E[o](x) += alpha_k max(e_k(x), 0)
                            double* o = out.row(c, y);
                            for (std::size_t x = 0; x < e.size(); ++x) {
                              o[x] += alpha * std::max(e[x], 0.0);
                            }
                          });
  }
  return out;
}

Image observe_analog(const RowSpectra& u, std::span<const double> gains,
                     const ObservationParams& params) {
  for (std::size_t k = 0; k < gains.size(); ++k) {
    if (!(gains[k] >= 0.0 && gains[k] <= 1.0)) {
      throw_usage_error("analog mode needs gains in [0, 1], but gain " + std::to_string(k) +
                        " is " + std::to_string(gains[k]));
    }
  }
  Image out(u.width, u.height, u.channels);
  const RowFFT fft(u.width);
  const PoissonSNR noise(params.snr);
  const auto filter = transfer_function_bins(gains, params.velocity, params.dt, u.width);
  for_each_filtered_row(u, filter, fft, params.threads,
                        [&](int c, int y, std::span<const double> e) {
                          // o(x) = PoissonSNR(e(x)), one stream per (channel, row)
                          RandomStream stream(params.seed, static_cast<std::uint64_t>(c), 0,
                                              static_cast<std::uint64_t>(y));
                          double* o = out.row(c, y);
                          for (std::size_t x = 0; x < e.size(); ++x) o[x] = noise(e[x], stream);
                        });
  return out;
}

Image observe_numerical(const RowSpectra& u, std::span<const double> gains,
                        const ObservationParams& params) {
  Image out(u.width, u.height, u.channels);
  const RowFFT fft(u.width);
  const PoissonSNR noise(params.snr);
  for (std::size_t k = 0; k < gains.size(); ++k) {
    const double alpha = gains[k];
    if (alpha == 0.0) continue;
    const auto filter =
        slot_transfer_function_bins(static_cast<int>(k), params.velocity, params.dt, u.width);
    for_each_filtered_row(u, filter, fft, params.threads,
                          [&](int c, int y, std::span<const double> e) {
                            // o(x) += alpha_k PoissonSNR(e_k(x)), one stream per (channel, slot,
                            // row)
                            RandomStream stream(params.seed, static_cast<std::uint64_t>(c), k,
                                                static_cast<std::uint64_t>(y));
                            double* o = out.row(c, y);
                            for (std::size_t x = 0; x < e.size(); ++x) {
                              o[x] += alpha * noise(e[x], stream);
                            }
                          });
  }
  return out;
}

}  // namespace fss
