// Photon noise (SPEC 3, the paper's Algorithm 1) and its random streams.
//
// Reproducibility: every (seed, channel, frame, row) has its own stream, so a
// row's noise does not depend on which thread draws it or in what order.
#pragma once

#include <cstdint>

namespace fss {

// xoshiro256** generator whose state is derived by splitmix64 from the seed
// and three stream coordinates.
class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame, std::uint64_t row);

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
// slot then has signal-to-noise ratio `snr`.
class PoissonSNR {
 public:
  explicit PoissonSNR(double snr);
  double lambda2() const { return lambda2_; }
  double operator()(double e, RandomStream& stream) const;

 private:
  double lambda2_;
};

}  // namespace fss
