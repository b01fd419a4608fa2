#include "fss/noise.h"

#include <algorithm>
#include <cmath>

namespace fss {

namespace {
std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame,
                           std::uint64_t row) {
  // Hash the four coordinates into one key, each step a full splitmix64 round,
  // then expand the key into the 256-bit state.
  std::uint64_t key = seed;
  for (const std::uint64_t coordinate : {channel, frame, row}) {
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

double RandomStream::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

double RandomStream::uniform_open_zero() {
  return static_cast<double>((next() >> 11) + 1) * 0x1.0p-53;
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
  return std::max(0.0, std::round(lambda + std::sqrt(lambda) * stream.standard_normal()));
}

PoissonSNR::PoissonSNR(double snr) : lambda2_(snr * snr / 100.0) {}

double PoissonSNR::operator()(double e, RandomStream& stream) const {
  // P / lambda2 with P ~ Poisson(max(e, 0) lambda2)
  return poisson_variate(std::max(e, 0.0) * lambda2_, stream) / lambda2_;
}

}  // namespace fss
