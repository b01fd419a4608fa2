// A ziggurat standard normal (Marsaglia and Tsang, 2000) and an inline
// xoshiro256** to feed it, for the micro-benchmark only: the fastest scalar normal generator we
// could build, the floor the per-frame sampler is measured against. Not used by the simulator (its
// streams are Box-Muller's, docs/method.md §3).
//
// The area under f(x) = exp(-x^2 / 2), x >= 0, is covered by 128 horizontal
// layers of equal area v: layer i (1 <= i < 128) is the rectangle
// [0, x_i] x [f(x_i), f(x_{i+1})] with x_1 = r > x_2 > ... > x_128 = 0; layer
// 0 is [0, r] x [0, f(r)] plus the tail beyond r, drawn as a rectangle of
// width x_0 = v / f(r). A draw picks a layer and x = U x_i: if x < x_{i+1}
// the point is under the curve (about 99% of draws: one 64-bit output, one
// multiplication, one comparison); otherwise it tests the wedge, or draws the
// tail for layer 0.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "model/noise.h"

namespace fss_bench {

// xoshiro256** (Blackman and Vigna): the same generator as
// fss::RandomStream, whose next() is inline too (noise.h), and as fast alone
// (0.82 ns a draw each, bench/run.sh of 2026-11-25); but a ziggurat fed from
// this bare state ran faster (346 against 312 M normals/s), so it stays as the
// stricter floor. Its state is 4 outputs of a RandomStream.
class InlineXoshiro {
 public:
  explicit InlineXoshiro(fss::RandomStream seed_stream) {
    for (auto& word : state_) word = seed_stream.next();
  }
  std::uint64_t next() {
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
  // Uniform on [0, 1) and on (0, 1], 53 bits.
  double uniform() {
    return static_cast<double>(static_cast<std::int64_t>(next() >> 11)) * 0x1.0p-53;
  }
  double uniform_open_zero() {
    return static_cast<double>(static_cast<std::int64_t>((next() >> 11) + 1)) * 0x1.0p-53;
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

class ZigguratNormal {
 public:
  ZigguratNormal() {
    // r and v for 128 layers: v = r f(r) + the tail's area, and the layers
    // close at x_128 = 0.
    constexpr double kR = 3.442619855899;
    constexpr double kV = 9.91256303526217e-3;
    x_[0] = kV / f(kR);
    x_[1] = kR;
    // Layer i has area v: x_i (f(x_{i+1}) - f(x_i)) = v.
    for (int i = 1; i < kLayers - 1; ++i)
      x_[i + 1] = std::sqrt(-2.0 * std::log(kV / x_[i] + f(x_[i])));
    x_[kLayers] = 0.0;
    for (int i = 0; i <= kLayers; ++i) f_[i] = f(x_[i]);
  }

  // Generator: anything with next(), uniform() and uniform_open_zero() as
  // fss::RandomStream has them.
  template <typename Generator>
  double operator()(Generator& stream) const {
    for (;;) {
      const std::uint64_t bits = stream.next();
      const int i = static_cast<int>(bits & (kLayers - 1));
      // Bit 7 is the sign, moved to the double's sign bit: a branch on a
      // random bit would be mispredicted half the time.
      const std::uint64_t sign = (bits & kLayers) << 56;
      const double u = static_cast<double>(static_cast<std::int64_t>(bits >> 11)) * 0x1.0p-53;
      const double x = u * x_[i];
      if (x < x_[i + 1]) return with_sign(x, sign);  // inside the layer's inner rectangle
      if (i == 0) return with_sign(tail(stream), sign);
      // The wedge: a uniform height in [f(x_i), f(x_{i+1})] under f(x)?
      const double y = f_[i] + stream.uniform() * (f_[i + 1] - f_[i]);
      if (y < f(x)) return with_sign(x, sign);
    }
  }

 private:
  static constexpr int kLayers = 128;
  static double f(double x) { return std::exp(-0.5 * x * x); }
  static double with_sign(double x, std::uint64_t sign) {
    return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) ^ sign);
  }

  // Marsaglia's tail beyond r: a = -ln(U1) / r, b = -ln(U2) until 2 b > a^2.
  template <typename Generator>
  static double tail(Generator& stream) {
    constexpr double kR = 3.442619855899;
    for (;;) {
      const double a = -std::log(stream.uniform_open_zero()) / kR;
      const double b = -std::log(stream.uniform_open_zero());
      if (2.0 * b > a * a) return kR + a;
    }
  }

  std::array<double, kLayers + 1> x_{};
  std::array<double, kLayers + 1> f_{};
};

}  // namespace fss_bench
