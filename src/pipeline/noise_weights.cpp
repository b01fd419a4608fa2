#include "fss/pipeline/noise_weights.h"

#include <algorithm>
#include <complex>
#include <string>

#include "fss/core/error.h"
#include "fss/core/fft.h"
#include "fss/model/transfer.h"

namespace fss {

namespace {

// k = IDFT(1 / K) on the n-point grid, 1 / K taken as 0 where K = 0 (as the
// restoration does): the inverse filter applied to a unit impulse at 0,
// whose DFT is 1 at every bin.
std::vector<double> inverse_filter_kernel(std::span<const double> gains, double velocity, double dt,
                                          int n) {
  std::vector<Complex> inverse = transfer_function_bins(gains, velocity, dt, n);
  for (Complex& k : inverse) k = k == Complex(0.0) ? Complex(0.0) : 1.0 / k;
  const RowFFT& fft = RowFFT::for_size(n);
  RowFFT::Workspace workspace(n);
  std::fill(workspace.spectrum().begin(), workspace.spectrum().end(), Complex(1.0));
  fft.inverse_filtered(workspace, inverse);
  return {workspace.real().begin(), workspace.real().end()};
}

void check_arguments(const Geometry& g, std::span<const double> gains, int first, int end) {
  if (g.observed_width < 1 || g.mirror_width != 2 * g.observed_width || g.output_width < 1) {
    throw_usage_error("noise weights need a geometry with an observed crop and an output: Wa = " +
                      std::to_string(g.observed_width) + ", 2 Wa = " +
                      std::to_string(g.mirror_width) + ", Wo = " + std::to_string(g.output_width));
  }
  if (gains.empty()) throw_usage_error("noise weights need a code with at least one gain");
  if (first < 0 || end > g.output_width || first >= end) {
    throw_usage_error("noise weight window [" + std::to_string(first) + ", " + std::to_string(end) +
                      ") is empty or outside the output [0, " + std::to_string(g.output_width) +
                      ")");
  }
}

}  // namespace

std::vector<double> noise_energy_weights(const Geometry& geometry, std::span<const double> gains,
                                         double restore_velocity, double dt, int window_first,
                                         int window_end) {
  check_arguments(geometry, gains, window_first, window_end);
  const int n = geometry.mirror_width;
  const int wa = geometry.observed_width;
  // The kernel twice over, so that (i mod n) is i for every i in [0, 2n).
  std::vector<double> k = inverse_filter_kernel(gains, restore_velocity, dt, n);
  k.insert(k.end(), k.begin(), k.end());
  // Output column x is deconvolved column x' = x + 2h, in [0, n).
  const int x_first = window_first + 2 * geometry.half_blur;
  const int x_end = window_end + 2 * geometry.half_blur;
  std::vector<double> weights(static_cast<std::size_t>(wa));
  for (int j = 0; j < wa; ++j) {
    // w_x(j) = k[(x' - j) mod n] + k[(x' + j + 1) mod n]
    const double* direct = k.data() + (n - j);
    const double* mirrored = k.data() + (j + 1);
    double sum = 0.0;
    for (int x = x_first; x < x_end; ++x) {
      const double w = direct[x] + mirrored[x];
      sum += w * w;
    }
    weights[static_cast<std::size_t>(j)] = sum;
  }
  return weights;
}

}  // namespace fss
