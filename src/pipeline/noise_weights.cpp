#include "pipeline/noise_weights.h"

#include <algorithm>
#include <complex>
#include <string>

#include "core/fft.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"
#include "pipeline/restore.h"

namespace fss {

namespace {

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
  return noise_energy_weights(
      geometry, inverse_filter_impulse_response(gains, restore_velocity, dt, geometry.mirror_width),
      window_first, window_end);
}

std::vector<double> noise_energy_weights(const Geometry& geometry, std::vector<double> k,
                                         int window_first, int window_end) {
  const std::vector<double> one_gain{1.0};
  check_arguments(geometry, one_gain, window_first, window_end);
  const int n = geometry.mirror_width;
  const int wa = geometry.observed_width;
  if (k.size() != static_cast<std::size_t>(n)) {
    throw_usage_error("noise weights need an impulse response of " + std::to_string(n) +
                      " values, got " + std::to_string(k.size()));
  }
  // The kernel twice over, so that (i mod n) is i for every i in [0, 2n).
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
