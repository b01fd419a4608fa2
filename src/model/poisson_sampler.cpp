// Photon noise of one elementary exposure (poisson_sampler.h). Compiled with
// the samplers' flags (CMakeLists.txt), so that its row loops vectorize.
#include "model/poisson_sampler.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

#include "core/vectorize.h"
#include "fss/core/error.h"

namespace fss {

double checked_lambda2(double snr) {
  const double lambda2 = snr * snr / 100.0;
  if (!(std::isfinite(lambda2) && lambda2 >= DBL_MIN)) {
    throw_usage_error("snr = " + format_exact(snr) +
                      " is out of range: snr^2 / 100 must be a finite, nonzero double "
                      "(snr between 1.5e-153 and 1.3e155)");
  }
  return lambda2;
}

double poisson_variate(double lambda, RandomStream& stream) {
  if (!(lambda > 0.0)) return 0.0;
  if (lambda < kKnuthLimit) {
    // Knuth: multiply uniforms until the product is <= exp(-lambda); the
    // variate is the number of multiplications minus one.
    const double limit = std::exp(-lambda);
    double product = stream.uniform();
    double count = 0.0;
    while (product > limit) {
      product *= stream.uniform();
      count += 1.0;
    }
    return count;
  }
  // Normal approximation, rounded; a negative value (probability < 1e-12 at
  // lambda = 50) is clamped to 0.
  return round_nonnegative(lambda + std::sqrt(lambda) * stream.standard_normal());
}

PoissonSNR::PoissonSNR(double snr) : lambda2_(checked_lambda2(snr)) {}

double PoissonSNR::operator()(double e, RandomStream& stream) const {
  // P / lambda2 with P ~ Poisson(max(e, 0) lambda2)
  return poisson_variate(std::max(e, 0.0) * lambda2_, stream) / lambda2_;
}

double poisson_snr_variance(double e, double lambda2) {
  // Var(P / lambda2) = (lambda [+ 1/12 on the normal branch]) / lambda2^2
  const double signal = std::max(e, 0.0);
  const double rounding = signal * lambda2 >= kKnuthLimit ? 1.0 / (12.0 * lambda2 * lambda2) : 0.0;
  return signal / lambda2 + rounding;
}

PoissonRowSampler::PoissonRowSampler(double snr) : lambda2_(checked_lambda2(snr)) {}

void PoissonRowSampler::draw_charge(std::span<const double> lambda, const RowNoiseId& id,
                                    std::size_t knuth_pixels) {
  const std::size_t n = lambda.size();
  draw_normals(lane_stream(id, id.frame, NoiseLane::kFrameNormal), n, u1_, u2_, normals_);
  if (knuth_pixels == 0) return;
  RandomStream knuth_stream = lane_stream(id, id.frame, NoiseLane::kFrameKnuth);
  for (std::size_t x = 0; x < n; ++x) {
    if (lambda[x] < kKnuthLimit) normals_[x] = poisson_variate(lambda[x], knuth_stream);
  }
}

std::size_t PoissonRowSampler::intensities_of(std::span<const double> e, double dark,
                                              std::vector<double>& lambda_row,
                                              std::vector<double>& root_row) const {
  const std::size_t n = e.size();
  lambda_row.resize(n);
  root_row.resize(n);
  std::size_t knuth_pixels = 0;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    // Locals, not the captured references, so that the loop vectorizes.
    const double* __restrict intensity = e.data();
    double* __restrict lambda = lambda_row.data();
    double* __restrict root = root_row.data();
    const double lambda2 = lambda2_;
    const double dark_electrons = dark;
    std::size_t count = 0;
    for (std::size_t x = 0; x < n; ++x) {
      lambda[x] = std::max(intensity[x], 0.0) * lambda2 + dark_electrons;
      root[x] = std::sqrt(lambda[x]);
      count += lambda[x] < kKnuthLimit ? 1 : 0;
    }
    knuth_pixels = count;
  });
  return knuth_pixels;
}

void PoissonRowSampler::accumulate(std::span<const double> e, const RowNoiseId& id, double gain,
                                   std::span<double> out) {
  const std::size_t knuth_pixels = intensities_of(e, 0.0, lambda_, root_);
  accumulate(Intensities{lambda_, root_, knuth_pixels}, id, gain, out);
}

void PoissonRowSampler::accumulate(const Intensities& row, const RowNoiseId& id, double gain,
                                   std::span<double> out) {
  const std::size_t n = row.lambda.size();
  // One normal per pixel, normal x for pixel x; Knuth's branch where
  // lambda < 50 takes the place of the pixel's unused normal.
  draw_charge(row.lambda, id, row.knuth_pixels);
  // Normal branch elsewhere: P = round(lambda + sqrt(lambda) N);
  // out += gain P / lambda2.
  const double scale = gain / lambda2_;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict lambda = row.lambda.data();
    const double* __restrict root = row.root.data();
    const double* __restrict normal = normals_.data();
    double* __restrict sum = out.data();
    const double factor = scale;
    for (std::size_t x = 0; x < n; ++x) {
      const double rounded = round_nonnegative(lambda[x] + root[x] * normal[x]);
      sum[x] += factor * (lambda[x] < kKnuthLimit ? normal[x] : rounded);
    }
  });
}

void PoissonRowSampler::accumulate_readout(std::span<const double> e, const RowNoiseId& id,
                                           double gain, const SensorReadout& readout,
                                           std::span<double> out) {
  const std::size_t n = e.size();
  // The charge P, drawn as accumulate() draws it: normals from lane 0, and
  // Knuth's variates from lane 1 in place of the unused normals.
  // (Two statements: the span of lambda_ must be taken after it is resized.)
  const std::size_t knuth_pixels = intensities_of(e, readout.dark_electrons, lambda_, root_);
  draw_charge(lambda_, id, knuth_pixels);
  // The read noise's normals from lane 4 (zeros without read noise).
  if (readout.read_noise_electrons != 0.0) {
    draw_normals(lane_stream(id, id.frame, NoiseLane::kReadNoise), n, u1_, u2_, read_normals_,
                 /*portable=*/true);
  } else {
    read_normals_.assign(n, 0.0);
  }
  // out += gain * read(P, R) / lambda2 (SensorReadout::read, inline so that
  // the loop vectorizes)
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict lambda = lambda_.data();
    const double* __restrict root = root_.data();
    const double* __restrict normal = normals_.data();
    const double* __restrict read = read_normals_.data();
    double* __restrict sum = out.data();
    const double scale = gain / lambda2_;
    const double well = readout.full_well_electrons;
    const double sigma = readout.read_noise_electrons;
    const double dark = readout.dark_electrons;
    const bool adc = readout.adc();
    const double adc_gain = adc ? readout.adc_gain_electrons_per_count : 1.0;
    const double adc_max = readout.adc_max_counts;
    for (std::size_t x = 0; x < n; ++x) {
      const double rounded = round_nonnegative(lambda[x] + root[x] * normal[x]);
      const double charge = lambda[x] < kKnuthLimit ? normal[x] : rounded;
      const double q = std::min(charge, well) + sigma * read[x];
      const double counted = std::min(round_nonnegative(q / adc_gain), adc_max) * adc_gain;
      sum[x] += scale * ((adc ? counted : q) - dark);
    }
  });
}

void PoissonRowSampler::add_read_noise(const RowNoiseId& id, double scale, std::span<double> out) {
  draw_normals(lane_stream(id, id.frame, NoiseLane::kReadNoise), out.size(), u1_, u2_,
               read_normals_, /*portable=*/true);
  for (std::size_t x = 0; x < out.size(); ++x) out[x] += scale * read_normals_[x];
}

}  // namespace fss
