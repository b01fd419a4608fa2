#include "fss/pipeline/restore.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

// True when n's prime factors are all 2, 3, 5 or 7.
bool seven_smooth(int n) {
  for (const int p : {2, 3, 5, 7}) {
    while (n % p == 0) n /= p;
  }
  return n == 1;
}

// h = IDFT_n(inverse), the impulse response of the filter `inverse` (half
// spectrum), as inverse_filter_row applies it.
std::vector<double> impulse_response(const std::vector<Complex>& inverse, int n) {
  const RowFFT& fft = RowFFT::for_size(n);
  RowFFT::Workspace workspace(n);
  std::fill(workspace.spectrum().begin(), workspace.spectrum().end(), Complex(1.0));
  fft.inverse_filtered(workspace, inverse);
  return {workspace.real().begin(), workspace.real().end()};
}

// DFT_m(g) / m with g[t] = h[(t + t0) mod N] for t < T = N + Wo - 1, 0 beyond,
// t0 = 2h - N + 1: restored column c = r[c + 2h] = sum_j m[j] h[(c + 2h - j)
// mod N], and c + 2h - j runs over [t0, t0 + T) for j in [0, N), so r[c + 2h]
// = (m * g)[c + N - 1], a linear convolution that a circular one of length
// m >= T gives without wrap. The 1 / m of the inverse DFT is folded in.
std::vector<Complex> convolution_filter(const std::vector<Complex>& inverse, const Geometry& g,
                                        int m) {
  const int n = g.mirror_width;
  const std::vector<double> h = impulse_response(inverse, n);
  const int t0 = 2 * g.half_blur - n + 1;
  const int taps = n + g.output_width - 1;
  const RowFFT& fft = RowFFT::for_size(m);
  RowFFT::Workspace workspace(m);
  const std::span<double> kernel = workspace.real();
  std::fill(kernel.begin(), kernel.end(), 0.0);
  for (int t = 0; t < taps; ++t) {
    const int lag = ((t + t0) % n + n) % n;
    kernel[static_cast<std::size_t>(t)] = h[static_cast<std::size_t>(lag)] / m;
  }
  fft.forward(workspace);
  return {workspace.spectrum().begin(), workspace.spectrum().end()};
}

// The linear convolution's round-off is spread over every frequency, at about
// eps sup|1/K| times the row's magnitude, K(0) times the image's; the grid's is
// eps times each bin's own gain. The convolution is used only while
// sup|1/K| |K(0)| stays below this: measured, 3.3e3 gave a largest difference
// of 1e-12 from the grid on a row of values up to 255 (the paper's codes at
// |v| dt <= 1 are below 30), and a kernel near a zero of K (1e16) differences
// of 5 to 22 gray levels, where the grid's bins keep the mirror row's exact
// cancellations.
constexpr double kMaxConvolutionConditioning = 1e6;

// sup_i |1/K_i| |K(0)| over the grid's bins, infinity when K(0) = 0.
double conditioning(const std::vector<Complex>& inverse) {
  if (inverse.empty() || inverse[0] == Complex(0.0)) return std::numeric_limits<double>::infinity();
  double largest = 0.0;
  for (const Complex& k : inverse) largest = std::max(largest, std::abs(k));
  return largest / std::abs(inverse[0]);
}

}  // namespace

int restoration_transform_length(const Geometry& geometry) {
  const int n = geometry.mirror_width;
  if (seven_smooth(n)) return n;
  const int taps = n + geometry.output_width - 1;
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
  return impulse_response(inverse_transfer_bins(gains, velocity, dt, n, &zero_bins), n);
}

RowRestorer::RowRestorer(const Geometry& geometry, std::span<const double> gains, double velocity,
                         double dt)
    : geometry_(geometry),
      inverse_(inverse_transfer_bins(gains, velocity, dt, geometry.mirror_width, &zero_bins_)),
      fft_(RowFFT::for_size(conditioning(inverse_) <= kMaxConvolutionConditioning
                                ? restoration_transform_length(geometry)
                                : geometry.mirror_width)) {
  fft_.prepare();  // both directions are used for every row
  if (fft_.size() != geometry.mirror_width) {
    convolution_ = convolution_filter(inverse_, geometry, fft_.size());
    inverse_ = {};
  }
}

std::size_t RowRestorer::bytes() const {
  return sizeof(Complex) * (inverse_.size() + convolution_.size());
}

void RowRestorer::restore(const double* observation, Scratch& scratch, double* restored) const {
  const int wa = geometry_.observed_width;
  const double* crop = observation + geometry_.half_blur;  // observed crop [h, h + Wa)
  const std::span<double> buffer = scratch.workspace.real();
  std::copy(crop, crop + wa, buffer.begin());
  std::reverse_copy(crop, crop + wa, buffer.begin() + wa);  // column j >= Wa is 2 Wa - 1 - j
  if (convolution_.empty()) {
    inverse_filter_row(fft_, inverse_, scratch.workspace);
    const double* deconvolved = buffer.data() + 2 * geometry_.half_blur;
    std::copy(deconvolved, deconvolved + geometry_.output_width, restored);
    return;
  }
  // The linear convolution (convolution_filter): the mirror row zero-padded,
  // restored column c at c + N - 1.
  std::fill(buffer.begin() + 2 * wa, buffer.end(), 0.0);
  fft_.forward(scratch.workspace);
  multiply_half_spectrum(scratch.workspace.spectrum(), convolution_, fft_.size());
  fft_.inverse(scratch.workspace);
  const double* convolved = buffer.data() + (2 * wa - 1);
  std::copy(convolved, convolved + geometry_.output_width, restored);
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
