#include "pipeline/restoration_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/fft.h"
#include "fss/model/kernel.h"
#include "pipeline/restore.h"

namespace fss {

namespace {

// H from K bin by bin by `formula(k, i)`, 0 where K vanishes.
template <typename Formula>
FilterBins filter_from_transfer(std::span<const double> gains, double velocity, double dt, int n,
                                const Formula& formula) {
  FilterBins filter;
  filter.h = transfer_function_bins(gains, velocity, dt, n);
  const double scale = transfer_scale(gains, dt);
  for (std::size_t i = 0; i < filter.h.size(); ++i) {
    Complex& k = filter.h[i];
    if (transfer_vanishes(std::abs(k), scale)) {
      ++filter.zero_bins;
      k = Complex(0.0);
    } else {
      k = formula(k, i);
    }
  }
  return filter;
}

}  // namespace

FilterBins inverse_filter_bins(std::span<const double> gains, double velocity, double dt, int n) {
  FilterBins filter;
  filter.h = inverse_transfer_bins(gains, velocity, dt, n, &filter.zero_bins);
  return filter;
}

FilterBins tikhonov_filter_bins(std::span<const double> gains, double velocity, double dt, int n,
                                double lambda) {
  const double kappa = transfer_scale(gains, dt);
  const double mu = lambda * kappa * kappa;
  // H = conj(K) / (|K|^2 + lambda kappa^2)
  return filter_from_transfer(gains, velocity, dt, n, [&](Complex k, std::size_t) {
    return std::conj(k) / (std::norm(k) + mu);
  });
}

FilterBins wiener_filter_bins(std::span<const double> gains, double velocity, double dt, int n,
                              std::span<const double> signal_power, double noise_power) {
  return filter_from_transfer(gains, velocity, dt, n, [&](Complex k, std::size_t i) {
    const double s = signal_power[i];
    if (std::isinf(s)) return 1.0 / k;  // S / (|K|^2 S + N) -> 1 / |K|^2
    // H = conj(K) S / (|K|^2 S + N)
    const double denominator = std::norm(k) * s + noise_power;
    return denominator > 0.0 ? std::conj(k) * (s / denominator) : Complex(0.0);
  });
}

std::vector<double> power_law_signal_power(int n, double gamma, double level) {
  std::vector<double> s(static_cast<std::size_t>(n / 2 + 1));
  s[0] = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < s.size(); ++i) {
    // S = c |xi|^-gamma
    s[i] = level * std::pow(std::abs(bin_frequency(static_cast<int>(i), n)), -gamma);
  }
  return s;
}

double filter_mean_power(std::span<const Complex> h, int n) {
  // Bins 1 .. ceil(n/2) - 1 stand for themselves and their conjugates.
  double sum = std::norm(h[0]);
  const int last = n / 2;
  for (int i = 1; i <= last; ++i) {
    const Complex value = h[static_cast<std::size_t>(i)];
    // the Nyquist bin of an even n applies Re(H) only (multiply_half_spectrum)
    sum += n % 2 == 0 && i == last ? value.real() * value.real() : 2.0 * std::norm(value);
  }
  return sum / n;
}

std::vector<double> filter_impulse_response(std::span<const Complex> h, int n) {
  // The filter applied to a unit impulse at 0, whose DFT is 1 at every bin.
  const RowFFT& fft = RowFFT::for_size(n);
  RowFFT::Workspace workspace(n);
  std::fill(workspace.spectrum().begin(), workspace.spectrum().end(), Complex(1.0));
  fft.inverse_filtered(workspace, h);
  return {workspace.real().begin(), workspace.real().end()};
}

}  // namespace fss
