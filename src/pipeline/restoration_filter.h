// The restoration filters H on the deconvolution grid (docs/method.md §12): the paper's inverse
// filter, Tikhonov and Wiener, each given by its bins 0 .. n/2 of the n-point real DFT of the
// mirror-extended row (n = 2 Wa), and the quantities of the exact prediction derived from H.
#pragma once

#include <span>
#include <vector>

#include "fss/model/transfer.h"

namespace fss {

// H's bins and the number of bins where K vanishes (transfer_vanishes), where every restoration
// takes H = 0.
struct FilterBins {
  std::vector<Complex> h;
  int zero_bins = 0;
};

// H = 1 / K.
FilterBins inverse_filter_bins(std::span<const double> gains, double velocity, double dt, int n);

// H = conj(K) / (|K|^2 + lambda kappa^2), kappa = dt sum |alpha_k|.
FilterBins tikhonov_filter_bins(std::span<const double> gains, double velocity, double dt, int n,
                                double lambda);

// H = conj(K) S / (|K|^2 S + N) with S = signal_power[i] (n/2 + 1 values, +infinity allowed:
// H = 1 / K there) and N = noise_power per bin, both in the unnormalised DFT's units; H = 0
// where the denominator is 0.
FilterBins wiener_filter_bins(std::span<const double> gains, double velocity, double dt, int n,
                              std::span<const double> signal_power, double noise_power);

// S_i = level |xi_i|^-gamma at the half-spectrum bins of the n grid (xi_i = bin_frequency), and
// S_0 = +infinity (a power law has unbounded power at xi = 0, where H is then 1 / K(0)).
std::vector<double> power_law_signal_power(int n, double gamma, double level);

// (1 / n) sum over the n bins of |H|^2: the restoration's white-noise gain, M for H = 1 / K.
double filter_mean_power(std::span<const Complex> h, int n);

// h = IDFT_n(H), H given by its half spectrum: the filter's impulse response on the n grid.
std::vector<double> filter_impulse_response(std::span<const Complex> h, int n);

}  // namespace fss
