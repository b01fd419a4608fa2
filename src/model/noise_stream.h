// The random streams of the photon noise (docs/method.md §3): splitmix64
// seeding, one xoshiro256** stream per (seed, channel, frame, row, lane), and
// Box-Muller normals drawn from a stream's uniforms.
//
// Reproducibility: every (seed, channel, frame, row) has its own streams, so
// a row's noise does not depend on which thread draws it or in what order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fss {

// splitmix64 (Steele, Lea and Flood): advances `state` by kSplitmix64Gamma
// and returns it mixed, so that nearby states give unrelated values. The one
// seed derivation of the library (noise streams, the optimizer's starts).
inline constexpr std::uint64_t kSplitmix64Gamma = 0x9e3779b97f4a7c15ULL;
std::uint64_t splitmix64(std::uint64_t& state);

// xoshiro256** generator whose state is derived by splitmix64 from the seed
// and three stream coordinates.
class RandomStream {
 public:
  // `lane` separates independent streams of the same row (see NoiseLane).
  RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame, std::uint64_t row,
               std::uint64_t lane = 0);

  // Inline (below): the row samplers draw one or two per pixel.
  std::uint64_t next();
  // Uniform on [0, 1), 53 random bits.
  double uniform();
  // Uniform on (0, 1]: never 0, so its logarithm is finite.
  double uniform_open_zero();
  // Standard normal by Box-Muller, N = sqrt(-2 ln U1) cos(2 pi U2); the sine
  // twin is kept and returned by the next call.
  double standard_normal();

 private:
  std::uint64_t state_[4];
  double spare_normal_ = 0.0;
  bool has_spare_ = false;
};

// Coordinates of the noise of one row of one elementary exposure.
struct RowNoiseId {
  std::uint64_t seed = 0;
  std::uint64_t channel = 0;
  std::uint64_t frame = 0;  // slot k (numerical), 0 (analog)
  std::uint64_t row = 0;
};

// The lanes of a row's random streams, RandomStream(seed, channel, frame,
// row, lane). Every lane is a separate xoshiro256** stream, so the samplers
// never share a variate:
//   kFrameNormal      per (seed, channel, frame k, row): PoissonRowSampler's
//                     Box-Muller uniforms, two per pair of pixels.
//   kFrameKnuth       per (seed, channel, frame k, row): PoissonRowSampler's
//                     Knuth uniforms, in pixel order.
//   kAggregateNormal  per (seed, channel, row), frame coordinate 0:
//                     AggregatedRowSampler's one normal per pixel, drawn in
//                     finish() like kFrameNormal's (pixel x gets output x of
//                     the Box-Muller batch).
//   kAggregateKnuth   per (seed, channel, frame k, row): AggregatedRowSampler's
//                     Knuth uniforms for frame k, in pixel order.
//   kReadNoise        per (seed, channel, frame k or 0 (analog), row): the
//                     sensor's read noise (accumulate_readout), one normal
//                     per pixel, pixel x gets output x of the Box-Muller
//                     batch. Drawn only when the read noise is on, so the
//                     other lanes' variates are those of a run without it.
//   kGroupPoisson     per (seed, channel, group g, row): AggregatedRowSampler's
//                     exact Poisson variates of group g (the g-th set of
//                     >= 2 frames with equal gains, docs/method.md §6c), the
//                     frame coordinate holding g; in pixel order.
enum class NoiseLane : std::uint64_t {
  kFrameNormal = 0,
  kFrameKnuth = 1,
  kAggregateNormal = 2,
  kAggregateKnuth = 3,
  kReadNoise = 4,
  kGroupPoisson = 5,
};

// The stream of `lane` for frame `frame` of the row (id.seed, id.channel,
// id.row).
inline RandomStream lane_stream(const RowNoiseId& id, std::uint64_t frame, NoiseLane lane) {
  return {id.seed, id.channel, frame, id.row, static_cast<std::uint64_t>(lane)};
}

// Box-Muller on arrays: z[2j] = sqrt(-2 ln u1[j]) cos(2 pi u2[j]) and
// z[2j+1] = sqrt(-2 ln u1[j]) sin(2 pi u2[j]), j < pairs; u1 in (0, 1].
// Vectorized with glibc's vector math library where available, 4 wide on
// processors with AVX2 (see noise_simd.cpp).
void box_muller_batch(const double* u1, const double* u2, double* z, std::size_t pairs);

// The same Box-Muller pairs computed with +, -, *, /, sqrt and exact bit
// operations only (ln, cos and sin as series with constant coefficients, see
// noise_stream.cpp), so every processor gives the same bits; within a few ulp of
// box_muller_batch. The aggregated sampler's normals, which are not rounded.
void box_muller_portable(const double* u1, const double* u2, double* z, std::size_t pairs);

// normals[x] for x < n (the buffer holds n rounded up to even): output x of
// a Box-Muller batch (box_muller_portable when `portable`, else
// box_muller_batch) whose pair j takes U1 = stream's (2j)-th draw,
// U2 = its (2j+1)-th; u1 and u2 are scratch.
void draw_normals(RandomStream stream, std::size_t n, std::vector<double>& u1,
                  std::vector<double>& u2, std::vector<double>& normals, bool portable = false);

namespace detail {
inline std::uint64_t rotate_left(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace detail

inline std::uint64_t RandomStream::next() {
  // xoshiro256** (Blackman and Vigna).
  const std::uint64_t result = detail::rotate_left(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = detail::rotate_left(state_[3], 45);
  return result;
}

// The 53-bit integers are converted as signed: one instruction, where an
// unsigned 64-bit conversion takes several on x86-64.
inline double RandomStream::uniform() {
  return static_cast<double>(static_cast<std::int64_t>(next() >> 11)) * 0x1.0p-53;
}

inline double RandomStream::uniform_open_zero() {
  return static_cast<double>(static_cast<std::int64_t>((next() >> 11) + 1)) * 0x1.0p-53;
}

}  // namespace fss
