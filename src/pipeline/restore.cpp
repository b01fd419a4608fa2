#include "pipeline/restore.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "core/fft.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/model/transfer.h"
#include "pipeline/restoration_filter.h"

namespace fss {

// Bins where K vanishes (transfer_vanishes: K is 0 there up to round-off)
// carry no information and are set to 0, so that the restoration drops those
// frequencies.
std::vector<Complex> inverse_transfer_bins(std::span<const double> gains, double velocity,
                                           double dt, int n, int* zero_bins) {
  std::vector<Complex> inverse = transfer_function_bins(gains, velocity, dt, n);
  const double scale = transfer_scale(gains, dt);
  *zero_bins = 0;
  for (Complex& k : inverse) {
    if (transfer_vanishes(std::abs(k), scale)) {
      ++*zero_bins;
      k = Complex(0.0);
    } else {
      k = 1.0 / k;
    }
  }
  return inverse;
}

namespace {

// r = IDFT(DFT(row) / K), in place in workspace.real().
void inverse_filter_row(const RowFFT& fft, const std::vector<Complex>& inverse,
                        RowFFT::Workspace& workspace) {
  fft.forward(workspace);
  fft.inverse_filtered(workspace, inverse);
}

// The folded convolution's filters. With x the observed crop (Wa values),
// the mirror row is m[j] = x[j] (j < Wa), x[N - 1 - j] (j >= Wa), and the
// restored column c is r[c + 2h] = sum_j m[j] k[(c + 2h - j) mod N], k the
// impulse response (N-periodic). Splitting j at Wa:
//   r[c + 2h] = sum_i x[i] k[(c + 2h - i) mod N] + sum_i x[i] k[(c + 2h + 1 + i) mod N]
//             = (x * gA)[c + Wa - 1] + (xr * gB)[c + Wa - 1],
// xr[i] = x[Wa - 1 - i] (x reversed), gA[t] = k[(t + 2h - Wa + 1) mod N],
// gB[t] = k[(t + 2h + 1) mod N], t in [0, T), T = Wa + Wo - 1: two linear
// convolutions whose outputs c + Wa - 1 a circular one of length m >= T gives
// without wrap. For real x, DFT_m(xr)[k] = w^{k (Wa - 1)} conj(X[k]), w =
// exp(-2 pi i / m), so Y = X GA + conj(X) GB' with GB' = w^{k (Wa - 1)} GB: one
// forward and one inverse transform of length m < N. Returns {GA, GB'} / m (the
// inverse DFT's 1 / m folded in).
std::pair<std::vector<Complex>, std::vector<Complex>> folded_filters(
    const std::vector<Complex>& inverse, const Geometry& g, int m) {
  const int n = g.mirror_width;
  const int wa = g.observed_width;
  const std::vector<double> k = filter_impulse_response(inverse, n);
  const int taps = wa + g.output_width - 1;
  const RowFFT& fft = RowFFT::for_size(m);
  RowFFT::Workspace workspace(m);
  // DFT_m(g) / m of g[t] = k[(t + first_lag) mod N], t < T.
  const auto spectrum_of = [&](int first_lag) {
    const std::span<double> kernel = workspace.real();
    std::fill(kernel.begin(), kernel.end(), 0.0);
    for (int t = 0; t < taps; ++t) {
      const int lag = ((t + first_lag) % n + n) % n;
      kernel[static_cast<std::size_t>(t)] = k[static_cast<std::size_t>(lag)] / m;
    }
    fft.forward(workspace);
    return std::vector<Complex>(workspace.spectrum().begin(), workspace.spectrum().end());
  };
  std::vector<Complex> a = spectrum_of(2 * g.half_blur - wa + 1);
  std::vector<Complex> b = spectrum_of(2 * g.half_blur + 1);
  for (std::size_t i = 0; i < b.size(); ++i) {
    // w^{i (Wa - 1)}, the phase taken modulo m so that it stays exact
    const auto turns = static_cast<double>((static_cast<long long>(i) * (wa - 1)) % m);
    b[i] *= std::polar(1.0, -2.0 * M_PI * turns / m);
  }
  return {std::move(a), std::move(b)};
}

// spectrum = X GA + conj(X) GB' (folded_filters), bin by bin.
void apply_folded_filters(std::span<Complex> spectrum, std::span<const Complex> direct,
                          std::span<const Complex> reversed) {
  for (std::size_t i = 0; i < spectrum.size(); ++i) {
    const double a = spectrum[i].real();
    const double b = spectrum[i].imag();
    const double c = direct[i].real();
    const double d = direct[i].imag();
    const double e = reversed[i].real();
    const double f = reversed[i].imag();
    // (a + ib)(c + id) + (a - ib)(e + if)
    spectrum[i] = Complex(a * c - b * d + (a * e + b * f), a * d + b * c + (a * f - b * e));
  }
}

// The folded convolution's round-off is spread over every frequency, at about
// eps sup|1/K| times the row's magnitude, K(0) times the image's; the grid's is
// eps times each bin's own gain. The convolution is used only while
// sup|1/K| |K(0)| stays below this, where that round-off stays far below a
// gray level (the paper's codes at |v| dt <= 1 are below 30); near a zero of
// K the grid's bins keep the mirror row's exact cancellations instead.
constexpr double kMaxFoldingConditioning = 1e6;

// sup_i |H_i| / |H_0| over the grid's bins (sup |1/K| |K(0)| for the
// inverse filter), infinity when H_0 = 0.
double conditioning(const std::vector<Complex>& inverse) {
  if (inverse.empty() || inverse[0] == Complex(0.0)) return std::numeric_limits<double>::infinity();
  double largest = 0.0;
  for (const Complex& k : inverse) largest = std::max(largest, std::abs(k));
  return largest / std::abs(inverse[0]);
}

}  // namespace

int restoration_transform_length(const Geometry& geometry) {
  const int taps = geometry.observed_width + geometry.output_width - 1;
  int best = 0;
  for (const int odd : {1, 3, 5, 7, 9, 15}) {
    int length = 2 * odd;
    while (length < taps) length *= 2;
    if (best == 0 || length < best) best = length;
  }
  return best;
}

std::vector<double> inverse_filter_impulse_response(std::span<const double> gains, double velocity,
                                                    double dt, int n) {
  int zero_bins = 0;
  return filter_impulse_response(inverse_transfer_bins(gains, velocity, dt, n, &zero_bins), n);
}

RowRestorer::RowRestorer(const Geometry& geometry, std::span<const double> gains, double velocity,
                         double dt)
    : RowRestorer(geometry, inverse_filter_bins(gains, velocity, dt, geometry.mirror_width)) {}

RowRestorer::RowRestorer(const Geometry& geometry, FilterBins filter)
    : geometry_(geometry),
      zero_bins_(filter.zero_bins),
      inverse_(std::move(filter.h)),
      fft_(RowFFT::for_size(conditioning(inverse_) <= kMaxFoldingConditioning
                                ? restoration_transform_length(geometry)
                                : geometry.mirror_width)) {
  fft_.prepare();  // both directions are used for every row
  if (conditioning(inverse_) <= kMaxFoldingConditioning) {
    auto [direct, reversed] = folded_filters(inverse_, geometry, fft_.size());
    direct_filter_ = std::move(direct);
    reversed_filter_ = std::move(reversed);
    inverse_ = {};
  }
}

std::size_t RowRestorer::bytes() const {
  return sizeof(Complex) * (inverse_.size() + direct_filter_.size() + reversed_filter_.size());
}

void RowRestorer::restore(const double* observation, Scratch& scratch, double* restored) const {
  restore_crop(observation + geometry_.half_blur, scratch, restored);  // observed crop [h, h + Wa)
}

void RowRestorer::restore_crop(const double* crop, Scratch& scratch, double* restored) const {
  const int wa = geometry_.observed_width;
  const std::span<double> buffer = scratch.workspace.real();
  std::copy(crop, crop + wa, buffer.begin());
  if (direct_filter_.empty()) {
    // The grid: the mirror row, r = IDFT_N(DFT_N(mirror) / K), columns [2h, 2h + Wo).
    std::reverse_copy(crop, crop + wa, buffer.begin() + wa);  // column j >= Wa is 2 Wa - 1 - j
    inverse_filter_row(fft_, inverse_, scratch.workspace);
    const double* deconvolved = buffer.data() + 2 * geometry_.half_blur;
    std::copy(deconvolved, deconvolved + geometry_.output_width, restored);
    return;
  }
  // The folded convolution (folded_filters): the crop zero-padded, restored
  // column c at c + Wa - 1.
  std::fill(buffer.begin() + wa, buffer.end(), 0.0);
  fft_.forward(scratch.workspace);
  apply_folded_filters(scratch.workspace.spectrum(), direct_filter_, reversed_filter_);
  fft_.inverse(scratch.workspace);
  const double* convolved = buffer.data() + (wa - 1);
  std::copy(convolved, convolved + geometry_.output_width, restored);
}

}  // namespace fss
