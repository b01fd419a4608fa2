// Photon noise (docs/method.md §3, the paper's Algorithm 1) and its random streams.
//
// Reproducibility: every (seed, channel, frame, row) has its own streams, so
// a row's noise does not depend on which thread draws it or in what order.
#pragma once

#include <cstdint>
#include <span>
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
  // `lane` separates independent streams of the same row (see PoissonRowSampler).
  RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame, std::uint64_t row,
               std::uint64_t lane = 0);

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

// Poisson variate of intensity lambda >= 0: Knuth's product of uniforms
// below kKnuthLimit, round(lambda + sqrt(lambda) N) above (never negative).
inline constexpr double kKnuthLimit = 50.0;
double poisson_variate(double lambda, RandomStream& stream);

// PoissonSNR(e) = P / lambda2, P ~ Poisson(max(e, 0) * lambda2),
// lambda2 = snr^2 / 100: a constant level 100 seen through one unit time
// slot then has signal-to-noise ratio `snr`. PoissonSNR and PoissonRowSampler
// throw a usage fss::Error unless lambda2 is a finite normal double (snr in
// about [1.5e-153, 1.3e155]): outside, every observation would be NaN.
class PoissonSNR {
 public:
  explicit PoissonSNR(double snr);
  double lambda2() const { return lambda2_; }
  double operator()(double e, RandomStream& stream) const;

 private:
  double lambda2_;
};

// Coordinates of the noise of one row of one elementary exposure.
struct RowNoiseId {
  std::uint64_t seed = 0;
  std::uint64_t channel = 0;
  std::uint64_t frame = 0;  // slot k (numerical), 0 (analog)
  std::uint64_t row = 0;
};

// PoissonSNR over a whole row, the same algorithm as PoissonSNR but drawn in
// batches so that it vectorizes: pixel x's normal is output x of a
// Box-Muller batch (both outputs of each pair used) fed by lane 0 of the
// row's stream; Knuth's uniforms come from lane 1, in pixel order. Holds
// scratch buffers: one sampler per thread.
class PoissonRowSampler {
 public:
  explicit PoissonRowSampler(double snr);
  // out[x] += gain * PoissonSNR(e[x]) for every x.
  void accumulate(std::span<const double> e, const RowNoiseId& id, double gain,
                  std::span<double> out);

 private:
  double lambda2_;
  std::vector<double> lambda_;
  std::vector<double> u1_;
  std::vector<double> u2_;
  std::vector<double> normals_;
};

// Box-Muller on arrays: z[2j] = sqrt(-2 ln u1[j]) cos(2 pi u2[j]) and
// z[2j+1] = sqrt(-2 ln u1[j]) sin(2 pi u2[j]), j < pairs; u1 in (0, 1].
// Vectorized with glibc's vector math library where available.
void box_muller_batch(const double* u1, const double* u2, double* z, std::size_t pairs);

// round(x) for x > 0 (halves away from zero), 0 for x <= 0; inline-friendly.
double round_nonnegative(double x);

}  // namespace fss
