// Photon noise of one elementary exposure (docs/method.md §3, the paper's
// Algorithm 1): the Poisson variate, PoissonSNR, its exact variance, and
// PoissonRowSampler, which draws it over a whole row.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fss/model/sensor.h"
#include "model/noise_stream.h"

namespace fss {

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

// lambda2 = snr^2 / 100; a usage fss::Error unless it is a finite normal
// double (snr in about [1.5e-153, 1.3e155]): 0 or infinity would turn every
// observation into NaN (0 / 0, inf * 0).
double checked_lambda2(double snr);

// Exact variance of PoissonSNR(e) as the samplers draw it, in units of e^2:
// Var(P) / lambda2^2 with Var(P) = lambda on Knuth's branch (lambda < 50)
// and lambda + 1/12 on the normal branch (the rounding of a normal of sd
// sqrt(lambda) >= 7 adds a uniform error of variance 1/12), so
//   Var = max(e, 0) / lambda2 + (lambda >= 50 ? 1 / (12 lambda2^2) : 0),
// lambda = max(e, 0) lambda2. The mean is max(e, 0) on both branches.
// (The normal branch's clamp at 0 and the lattice's effect on the mean and
// on 1/12 are below 1e-12 relative: P(N < -7) ~ 1e-12.)
double poisson_snr_variance(double e, double lambda2);

// PoissonSNR over a whole row, the same algorithm as PoissonSNR but drawn in
// batches so that it vectorizes: pixel x's normal is output x of a
// Box-Muller batch (both outputs of each pair used) fed by the frame row's
// kFrameNormal lane; Knuth's uniforms come from its kFrameKnuth lane, in
// pixel order (see NoiseLane). Holds scratch buffers: one sampler per thread.
class PoissonRowSampler {
 public:
  explicit PoissonRowSampler(double snr);
  double lambda2() const { return lambda2_; }
  // out[x] += gain * PoissonSNR(e[x]) for every x.
  void accumulate(std::span<const double> e, const RowNoiseId& id, double gain,
                  std::span<double> out);

  // A row's intensities lambda[x] = max(e[x], 0) lambda2 + dark (photo and
  // dark electrons, one Poisson; dark is 0 without a sensor) and their square
  // roots, with the number of pixels on Knuth's branch (lambda < 50): what
  // accumulate() and accumulate_readout() compute from e first. A row whose frames are circular
  // shifts of one exposure computes them once (intensities_of) and gives
  // each frame a window of them (the count is the same for every shift).
  struct Intensities {
    std::span<const double> lambda;
    std::span<const double> root;
    std::size_t knuth_pixels = 0;
  };
  // lambda and root (resized to e's size) of exposure e; returns the count.
  std::size_t intensities_of(std::span<const double> e, double dark, std::vector<double>& lambda,
                             std::vector<double>& root) const;
  // The same as accumulate(e, ...) for the exposure whose intensities these are.
  void accumulate(const Intensities& row, const RowNoiseId& id, double gain, std::span<double> out);
  // The same with a sensor (docs/method.md §10): out[x] += gain *
  // readout.read(P[x], R[x]) / lambda2, P[x] ~ Poisson(max(e[x], 0) lambda2 +
  // dark) drawn exactly as accumulate() draws it (photo and dark electrons
  // are one Poisson: a sum of independent Poissons), R[x] a standard normal
  // from the row's kReadNoise lane (box_muller_portable: the read noise is
  // not rounded without an ADC, so its bits must not depend on the
  // processor). Used only when the sensor is enabled.
  void accumulate_readout(std::span<const double> e, const RowNoiseId& id, double gain,
                          const SensorReadout& readout, std::span<double> out);
  // out[x] += scale * N[x], N standard normals from the row's kReadNoise lane
  // (box_muller_portable), as accumulate_readout draws its read noise: the
  // numerical mode's read noise summed over the frames of a linear sensor.
  void add_read_noise(const RowNoiseId& id, double scale, std::span<double> out);

 private:
  // normals_[x] = pixel x's normal (kFrameNormal lane), replaced by its
  // Knuth variate (kFrameKnuth lane, pixel order) where lambda[x] < 50.
  void draw_charge(std::span<const double> lambda, const RowNoiseId& id, std::size_t knuth_pixels);

  double lambda2_;
  std::vector<double> lambda_;
  std::vector<double> root_;
  std::vector<double> u1_;
  std::vector<double> u2_;
  std::vector<double> normals_;
  std::vector<double> read_normals_;
};

// round(x) for x > 0 (halves away from zero), 0 for x <= 0. Inline and
// branch-free, so that the samplers' loops over it vectorize: (x + 2^52) -
// 2^52 rounds x in [0, 2^52) to the nearest integer, ties to even (default
// rounding mode); a tie rounded down is moved up, giving round()'s ties away
// from zero. From 2^52 on, x is already an integer.
[[gnu::always_inline]] inline double round_nonnegative(double x) {
  const double nearest = (x + 0x1p52) - 0x1p52;
  const double rounded = nearest - x == -0.5 ? nearest + 1.0 : nearest;
  const double big = x >= 0x1p52 ? x : rounded;
  return x > 0.0 ? big : 0.0;
}

}  // namespace fss
