#include "fss/model/noise.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

#include "fss/core/error.h"

namespace fss {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += kSplitmix64Gamma);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

namespace {
std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// lambda2 = snr^2 / 100, refused unless it is a finite normal number: 0 or
// infinity would turn every observation into NaN (0 / 0, inf * 0).
double checked_lambda2(double snr) {
  const double lambda2 = snr * snr / 100.0;
  if (!(std::isfinite(lambda2) && lambda2 >= DBL_MIN)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "snr = %g is out of range: snr^2 / 100 must be a finite, nonzero double "
                  "(snr between 1.5e-153 and 1.3e155)",
                  snr);
    throw_usage_error(text);
  }
  return lambda2;
}
}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame,
                           std::uint64_t row, std::uint64_t lane) {
  // Hash the coordinates into one key, each step a full splitmix64 round,
  // then expand the key into the 256-bit state.
  std::uint64_t key = seed;
  for (const std::uint64_t coordinate : {channel, frame, row, lane}) {
    std::uint64_t x = key ^ rotl(coordinate + 0x632be59bd9b4e019ULL, 17);
    key = splitmix64(x);
  }
  for (auto& word : state_) word = splitmix64(key);
}

std::uint64_t RandomStream::next() {
  // xoshiro256** (Blackman and Vigna).
  const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotl(state_[3], 45);
  return result;
}

// The 53-bit integers are converted as signed: one instruction, where an
// unsigned 64-bit conversion takes several on x86-64.
double RandomStream::uniform() {
  return static_cast<double>(static_cast<std::int64_t>(next() >> 11)) * 0x1.0p-53;
}

double RandomStream::uniform_open_zero() {
  return static_cast<double>(static_cast<std::int64_t>((next() >> 11) + 1)) * 0x1.0p-53;
}

double RandomStream::standard_normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_normal_;
  }
  // N = sqrt(-2 ln U1) cos(2 pi U2), twin sqrt(-2 ln U1) sin(2 pi U2); U1 in (0, 1].
  const double radius = std::sqrt(-2.0 * std::log(uniform_open_zero()));
  const double angle = 2.0 * M_PI * uniform();
  spare_normal_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
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

double round_nonnegative(double x) {
  // Branch-free so that loops over it vectorize. (x + 2^52) - 2^52 rounds x
  // in [0, 2^52) to the nearest integer, ties to even (default rounding
  // mode); a tie rounded down is moved up, giving round()'s ties away from
  // zero. From 2^52 on, x is already an integer.
  const double nearest = (x + 0x1p52) - 0x1p52;
  const double rounded = nearest - x == -0.5 ? nearest + 1.0 : nearest;
  const double big = x >= 0x1p52 ? x : rounded;
  return x > 0.0 ? big : 0.0;
}

PoissonSNR::PoissonSNR(double snr) : lambda2_(checked_lambda2(snr)) {}

double PoissonSNR::operator()(double e, RandomStream& stream) const {
  // P / lambda2 with P ~ Poisson(max(e, 0) lambda2)
  return poisson_variate(std::max(e, 0.0) * lambda2_, stream) / lambda2_;
}

}  // namespace fss

namespace fss {

PoissonRowSampler::PoissonRowSampler(double snr) : lambda2_(checked_lambda2(snr)) {}

void PoissonRowSampler::accumulate(std::span<const double> e, const RowNoiseId& id, double gain,
                                   std::span<double> out) {
  const std::size_t n = e.size();
  const std::size_t pairs = (n + 1) / 2;
  lambda_.resize(n);
  u1_.resize(pairs);
  u2_.resize(pairs);
  normals_.resize(2 * pairs);
  double* __restrict lambda = lambda_.data();
  double* __restrict normal = normals_.data();
  for (std::size_t x = 0; x < n; ++x) lambda[x] = std::max(e[x], 0.0) * lambda2_;

  // One normal per pixel, normal x for pixel x, from lane 0 (pixels on
  // Knuth's branch leave theirs unused).
  RandomStream normal_stream(id.seed, id.channel, id.frame, id.row, 0);
  for (std::size_t j = 0; j < pairs; ++j) {
    u1_[j] = normal_stream.uniform_open_zero();
    u2_[j] = normal_stream.uniform();
  }
  box_muller_batch(u1_.data(), u2_.data(), normal, pairs);

  // Normal branch for every pixel, vectorized: P = round(lambda + sqrt(lambda) N).
  for (std::size_t x = 0; x < n; ++x) {
    normal[x] = round_nonnegative(lambda[x] + std::sqrt(lambda[x]) * normal[x]);
  }
  // Knuth's branch where lambda < 50, uniforms from lane 1, in pixel order.
  RandomStream knuth_stream(id.seed, id.channel, id.frame, id.row, 1);
  for (std::size_t x = 0; x < n; ++x) {
    if (lambda[x] < kKnuthLimit) normal[x] = poisson_variate(lambda[x], knuth_stream);
  }
  const double scale = gain / lambda2_;
  for (std::size_t x = 0; x < n; ++x) out[x] += scale * normal[x];  // gain * P / lambda2
}

}  // namespace fss
