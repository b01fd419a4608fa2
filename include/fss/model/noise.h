// Photon noise (docs/method.md §3, the paper's Algorithm 1) and its random streams.
//
// Reproducibility: every (seed, channel, frame, row) has its own streams, so
// a row's noise does not depend on which thread draws it or in what order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fss/model/sensor.h"

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
enum class NoiseLane : std::uint64_t {
  kFrameNormal = 0,
  kFrameKnuth = 1,
  kAggregateNormal = 2,
  kAggregateKnuth = 3,
  kReadNoise = 4,
};

// Exact variance of PoissonSNR(e) as the samplers draw it, in units of e^2:
// Var(P) / lambda2^2 with Var(P) = lambda on Knuth's branch (lambda < 50)
// and lambda + 1/12 on the normal branch (the rounding of a normal of sd
// sqrt(lambda) >= 7 adds a uniform error of variance 1/12), so
//   Var = max(e, 0) / lambda2 + (lambda >= 50 ? 1 / (12 lambda2^2) : 0),
// lambda = max(e, 0) lambda2. The mean is max(e, 0) on both branches.
// (The normal branch's clamp at 0 and the lattice's effect on the mean and
// on 1/12 are below 1e-12 relative: P(N < -7) ~ 1e-12.)
double poisson_snr_variance(double e, double lambda2);

// The numerical mode's observation of one row,
//   o[x] = sum_k alpha_k PoissonSNR(e_k[x]),
// with the normal-branch frames aggregated (docs/method.md §6c): for each
// pixel, the frames with lambda_k = max(e_k[x], 0) lambda2 >= 50 are
// replaced by ONE normal
//   A[x] = M[x] + sqrt(V[x]) N[x],   M = sum alpha_k lambda_k,
//                                    V = sum alpha_k^2 (lambda_k + 1/12),
// added as A[x] / lambda2; the frames with lambda_k < 50 are drawn one by
// one by Knuth's method, as PoissonRowSampler does. One normal per pixel and
// row instead of one per pixel and frame.
//
// What is the same as PoissonRowSampler: the mean and the variance of o[x]
// (each pixel's frames are independent, so both add up over frames; the
// normal-branch frame's variance is lambda_k + 1/12, see
// poisson_snr_variance), the Knuth-branch frames' distribution (the very
// same algorithm), and independence between pixels, rows and channels.
// What differs is the rounding lattice: the per-frame sampler adds alpha_k
// round(lambda_k + sqrt(lambda_k) N_k), integers times the gains, so o[x]
// lies on the lattice {sum_k alpha_k n_k} / lambda2; A is one continuous
// normal, not rounded, with each frame's rounding kept as the 1/12 in its
// variance. A is not rounded because the gains are arbitrary reals: the
// per-frame sum is not an integer unless every gain is, and rounding A would
// add a single 1/12 where the per-frame sum has one per frame, breaking the
// variance it must match. (With integer gains, such as the 0/1 codes,
// rounding A drawn with one 1/12 fewer would land on the per-frame lattice;
// one rule for every code was preferred: a frame's lattice step, |alpha_k|
// photons, is at most 1/7 of its standard deviation |alpha_k|
// sqrt(lambda_k).) Beyond the variance: both sums are symmetric about their
// mean on the normal branch (third cumulants 0); their fourth cumulants
// differ by the roundings', -sum alpha_k^4 / 120 photons^4, an excess
// kurtosis of at most 1 / (120 * 50^2) = 3.3e-6 since lambda_k >= 50; the
// per-frame sampler clamps each frame at 0 (probability about 1e-12 a frame),
// A does not. Different variates: the streams are the kAggregate lanes, so
// the aggregated and per-frame observations of one seed are independent
// draws. As A is not rounded, the last bits of N reach the output: N comes
// from box_muller_portable, which calls no libm or libmvec function (their
// variants differ by processor), so a given M and V give the same bits on
// every processor. (M and V come from e, whose last bits follow FFTW's
// processor-dependent codelets, as every observation's do.)
//
// Use, per row: add_frame() for each frame with a nonzero gain, then
// finish(). Each frame has its own Knuth stream, so the frames' order (or
// skipping a zero gain) changes no variate, only the rounding of the sums;
// the observer adds them in k order, as for the per-frame sampler. The
// Knuth-branch frames go straight into `out`; the normal-branch ones are
// summed into two row-sized accumulators, M and V, which finish() turns
// into the normal and resets for the next row: no frame's row is kept.
// Holds scratch buffers: one sampler per thread.
//
// Trials: everything but the variates is the same for every seed. A row's
// AggregatedRowPlan (M, V and the Knuth-branch frames' pixels and
// intensities), recorded while the row is drawn once, lets replay() draw the
// row again for any seed without its frames: the same bytes as add_frame()
// for each frame then finish().
struct AggregatedRowPlan {
  struct KnuthFrame {
    std::uint64_t frame = 0;
    double gain = 0.0;
    std::vector<std::uint32_t> pixels;  // in pixel order
    std::vector<double> lambdas;        // their intensities, lambda < 50
  };
  bool recorded = false;
  std::vector<double> mean;      // M; empty when no pixel had a normal-branch frame
  std::vector<double> variance;  // V
  std::vector<KnuthFrame> knuth;
  std::size_t knuth_pixels = 0;  // total over the frames
};

class AggregatedRowSampler {
 public:
  explicit AggregatedRowSampler(double snr);
  double lambda2() const { return lambda2_; }
  // Frame id.frame of row (id.seed, id.channel, id.row): out[x] +=
  // gain * PoissonSNR(e[x]) where lambda < 50, accumulated into M and V
  // otherwise. e and out have the row's width, the same for every frame.
  // With a `readout` (a linear sensor: dark current and read noise only,
  // docs/method.md §10), aggregated exactly: each lambda gains the dark
  // charge (a sum of Poissons is one Poisson), and every pixel's
  // M -= alpha dark (the dark-frame correction) and V += alpha^2 sigma_r^2
  // (a sum of independent normals is one normal); the full well and the ADC
  // are not applied (Simulate refuses them with aggregated noise).
  void add_frame(std::span<const double> e, const RowNoiseId& id, double gain,
                 std::span<double> out, const SensorReadout* readout = nullptr);

  // A frame's intensities as add_frame() computes them from e first:
  // lambda[x] = max(e[x], 0) lambda2 + dark, its normal-branch parts
  // (lambda and lambda + 1/12 where lambda >= 50, 0 elsewhere) and the count
  // of normal-branch pixels. A row whose frames are circular shifts of one
  // exposure computes them once (intensities_of) and gives each frame a
  // window of them (the count is the same for every shift).
  struct FrameIntensities {
    std::span<const double> lambda;
    std::span<const double> mean_part;
    std::span<const double> variance_part;
    std::size_t normal_pixels = 0;
  };
  struct IntensityRows {
    std::vector<double> lambda;
    std::vector<double> mean_part;
    std::vector<double> variance_part;
  };
  // Fills `rows` (resized to e's size) for exposure e; returns the count.
  std::size_t intensities_of(std::span<const double> e, double dark, IntensityRows& rows) const;
  // The same as add_frame(e, ...) for the exposure whose intensities these are.
  void add_frame(const FrameIntensities& frame, const RowNoiseId& id, double gain,
                 std::span<double> out, const SensorReadout* readout = nullptr);
  // out[x] += (M[x] + sqrt(V[x]) N[x]) / lambda2 with N from the row's
  // kAggregateNormal lane (id.frame is ignored), then M = V = 0. Draws
  // nothing when no pixel had a normal-branch frame.
  void finish(const RowNoiseId& id, std::span<double> out);

  // Records the row's plan during the next add_frame() calls and finish()
  // into `plan` (which must outlive them); finish() marks it recorded unless
  // its Knuth-branch pixel frames exceeded `max_knuth_pixels` (then it is
  // left empty and not recorded: that row is drawn from its frames).
  void record_next_row(AggregatedRowPlan* plan, std::size_t max_knuth_pixels);
  // The row of a recorded plan with the noise of (id.seed, id.channel,
  // id.row): out[x] += what add_frame() for each of its frames, then
  // finish(), would add.
  void replay(const AggregatedRowPlan& plan, const RowNoiseId& id, std::span<double> out);

 private:
  // A linear sensor's frame of gain alpha: M -= alpha dark, V += alpha^2 sigma_r^2.
  void add_readout_terms(double gain, const SensorReadout& readout);
  // The frame's pixels on Knuth's branch (lambda < 50, `knuth_pixels` of
  // them): out += gain P / lambda2, recorded into the plan being recorded.
  void add_knuth_branch(std::span<const double> lambda, std::size_t knuth_pixels,
                        const RowNoiseId& id, double gain, std::span<double> out);
  // out += (M + sqrt(V) N) / lambda2, N from the row's kAggregateNormal lane.
  void add_normals(std::span<const double> mean, std::span<const double> variance,
                   const RowNoiseId& id, std::span<double> out);

  double lambda2_;
  AggregatedRowPlan* plan_ = nullptr;  // being recorded
  std::size_t max_knuth_pixels_ = 0;
  bool has_frame_ = false;   // add_frame() was called since the last finish()
  bool has_normal_ = false;  // and some pixel of some frame was on the normal branch
  IntensityRows intensities_;
  std::vector<double> mean_;      // M, in photons
  std::vector<double> variance_;  // V, in photons^2
  std::vector<double> u1_;
  std::vector<double> u2_;
  std::vector<double> normals_;
};

// Box-Muller on arrays: z[2j] = sqrt(-2 ln u1[j]) cos(2 pi u2[j]) and
// z[2j+1] = sqrt(-2 ln u1[j]) sin(2 pi u2[j]), j < pairs; u1 in (0, 1].
// Vectorized with glibc's vector math library where available, 4 wide on
// processors with AVX2 (see noise_simd.cpp).
void box_muller_batch(const double* u1, const double* u2, double* z, std::size_t pairs);

// The same Box-Muller pairs computed with +, -, *, /, sqrt and exact bit
// operations only (ln, cos and sin as series with constant coefficients, see
// noise.cpp), so every processor gives the same bits; within a few ulp of
// box_muller_batch. The aggregated sampler's normals, which are not rounded.
void box_muller_portable(const double* u1, const double* u2, double* z, std::size_t pairs);

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
