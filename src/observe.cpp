#include "fss/observe.h"

#include <algorithm>
#include <cmath>
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

// The elementary exposures e_k = rowconv(u, K_k) of one row, k = 0 .. L-1.
// When s = v dt is an integer, K_k = K_0 exp(-i xi s k) is exactly a circular
// shift by s k pixels, so e_k(x) = e_0(x - s k) costs no transform; otherwise
// each e_k is its own inverse FFT.
class SlotExposures {
 public:
  SlotExposures(const RowSpectra& u, std::span<const double> gains, const ObservationParams& p)
      : width_(u.width), gains_(gains.begin(), gains.end()), fft_(RowFFT::for_size(u.width)) {
    const double s = p.velocity * p.dt;
    shift_ = std::nearbyint(s) == s && std::abs(s) < 1e9;
    if (shift_) {
      step_ = static_cast<long long>(s);
      filters_.push_back(slot_transfer_function_bins(0, p.velocity, p.dt, width_));
    } else {
      for (std::size_t k = 0; k < gains_.size(); ++k) {
        filters_.push_back(gains_[k] == 0.0 ? std::vector<Complex>()
                                            : slot_transfer_function_bins(
                                                  static_cast<int>(k), p.velocity, p.dt, width_));
      }
    }
  }

  int width() const { return width_; }
  const RowFFT& fft() const { return fft_; }

  // Calls fn(k, alpha_k, e_k) for every slot with alpha_k != 0, in slot order.
  template <typename Fn>
  void for_each(const Complex* row_spectrum, RowFFT::Workspace& workspace,
                std::vector<double>& shifted, const Fn& fn) const {
    const int bins = width_ / 2 + 1;
    if (shift_) {
      const std::span<const double> e0 = inverse(row_spectrum, bins, filters_[0], workspace);
      shifted.resize(static_cast<std::size_t>(width_));
      for (std::size_t k = 0; k < gains_.size(); ++k) {
        if (gains_[k] == 0.0) continue;
        // e_k(x) = e_0((x - s k) mod W)
        long long offset = (step_ * static_cast<long long>(k)) % width_;
        if (offset < 0) offset += width_;
        const auto o = static_cast<std::size_t>(offset);
        std::copy(e0.end() - static_cast<std::ptrdiff_t>(o), e0.end(), shifted.begin());
        std::copy(e0.begin(), e0.end() - static_cast<std::ptrdiff_t>(o),
                  shifted.begin() + static_cast<std::ptrdiff_t>(o));
        fn(k, gains_[k], std::span<const double>(shifted));
      }
    } else {
      for (std::size_t k = 0; k < gains_.size(); ++k) {
        if (gains_[k] == 0.0) continue;
        fn(k, gains_[k], inverse(row_spectrum, bins, filters_[k], workspace));
      }
    }
  }

 private:
  std::span<const double> inverse(const Complex* row_spectrum, int bins,
                                  const std::vector<Complex>& filter,
                                  RowFFT::Workspace& workspace) const {
    std::copy(row_spectrum, row_spectrum + bins, workspace.spectrum().begin());
    multiply_half_spectrum(workspace.spectrum(), filter, width_);
    fft_.inverse(workspace);
    const double inverse_n = 1.0 / width_;
    for (double& value : workspace.real()) value *= inverse_n;
    return workspace.real();
  }

  int width_;
  std::vector<double> gains_;
  const RowFFT& fft_;
  bool shift_ = false;
  long long step_ = 0;
  std::vector<std::vector<Complex>> filters_;
};

// For every row r = c * height + y: e = IDFT(U_r * filter), then
// sink(c, y, e) with e the real row already divided by the row length.
template <typename Sink>
void for_each_filtered_row(const RowSpectra& u, const std::vector<Complex>& filter, int threads,
                           const Sink& sink) {
  const int bins = u.spectrum_size();
  const double inverse_n = 1.0 / u.width;
  const RowFFT& fft = RowFFT::for_size(u.width);
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
  const auto filter = transfer_function_bins(gains, params.velocity, params.dt, u.width);
  for_each_filtered_row(u, filter, params.threads, [&](int c, int y, std::span<const double> e) {
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
  const SlotExposures slots(u, gains, params);
  parallel_for(u.channels * u.height, params.threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(u.width);
    std::vector<double> shifted;
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      double* o = out.row(c, y);
      slots.for_each(u.row(c, y), workspace, shifted,
                     [&](std::size_t, double alpha, std::span<const double> e) {
                       // E[o](x) = sum_k alpha_k max(e_k(x), 0)
                       for (std::size_t x = 0; x < e.size(); ++x)
                         o[x] += alpha * std::max(e[x], 0.0);
                     });
    }
  });
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
  const auto filter = transfer_function_bins(gains, params.velocity, params.dt, u.width);
  const RowFFT& fft = RowFFT::for_size(u.width);
  const int bins = u.spectrum_size();
  const double inverse_n = 1.0 / u.width;
  parallel_for(u.channels * u.height, params.threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(u.width);
    PoissonRowSampler sampler(params.snr);
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      std::copy(u.row(c, y), u.row(c, y) + bins, workspace.spectrum().begin());
      multiply_half_spectrum(workspace.spectrum(), filter, u.width);
      fft.inverse(workspace);
      for (double& value : workspace.real()) value *= inverse_n;
      // o(x) = PoissonSNR(e(x)), streams of (channel, frame 0, row)
      sampler.accumulate(
          workspace.real(),
          {params.seed, static_cast<std::uint64_t>(c), 0, static_cast<std::uint64_t>(y)}, 1.0,
          std::span<double>(out.row(c, y), static_cast<std::size_t>(u.width)));
    }
  });
  return out;
}

Image observe_numerical(const RowSpectra& u, std::span<const double> gains,
                        const ObservationParams& params) {
  Image out(u.width, u.height, u.channels);
  const SlotExposures slots(u, gains, params);
  parallel_for(u.channels * u.height, params.threads, [&](int begin, int end) {
    RowFFT::Workspace workspace(u.width);
    PoissonRowSampler sampler(params.snr);
    std::vector<double> shifted;
    for (int r = begin; r < end; ++r) {
      const int c = r / u.height;
      const int y = r % u.height;
      const std::span<double> o(out.row(c, y), static_cast<std::size_t>(u.width));
      slots.for_each(
          u.row(c, y), workspace, shifted,
          [&](std::size_t k, double alpha, std::span<const double> e) {
            // o(x) += alpha_k PoissonSNR(e_k(x)), streams of (channel, slot, row)
            sampler.accumulate(
                e, {params.seed, static_cast<std::uint64_t>(c), k, static_cast<std::uint64_t>(y)},
                alpha, o);
          });
    }
  });
  return out;
}

}  // namespace fss
