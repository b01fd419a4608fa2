// Code design: generating, analysing and optimizing flutter shutter codes
// without simulating an image. Conventions: image.h.
//
// Figure of merit (SPEC 6). The SNR of the restored image of a constant
// landscape at level 100 is
//   SNR_100 = 100 / sqrt(100 Q (100 / snr^2) M) = snr / sqrt(Q M),
// with Q = dt sum alpha_k^2 (numerical) or dt sum alpha_k (analog) and M the
// mean of 1 / |K(xi)|^2 over the band xi in [-pi, pi]. The product Q M (the
// "noise figure") is the only thing a code changes: SNR_100 is proportional to
// snr, and the ratio of two codes' SNR_100 does not depend on snr at all.
// Scaling a numerical code by c leaves Q M unchanged (Q ~ c^2, M ~ 1 / c^2);
// scaling an analog code by c divides Q M by c.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fss/model/code.h"

namespace fss {

// Number of midpoint nodes on [0, pi] used to average 1 / |K|^2 over the band
// when no DFT grid is given (|K| is even for real gains, so the half band
// suffices; this is an 8192-node midpoint rule on [-pi, pi]).
inline constexpr int kBandGridPoints = 4096;

// Longest codes generate_code and optimize_code accept (the sinc and MIP
// integrals cost O(L) each; the optimizer's band basis holds 2 G L doubles).
inline constexpr int kMaxGeneratedCodeLength = 10000;
inline constexpr int kMaxOptimizedCodeLength = 4096;

// ---------------------------------------------------------------------------
// Generation (SPEC 7).

enum class CodeFamily { kSinc, kMip, kRandom, kSnapshot, kAccumulation };
std::string to_string(CodeFamily family);
std::optional<CodeFamily> code_family_from_string(std::string_view text);

// True when the sinc and MIP constructions are defined: 0 < |v| dt < 2 (the
// band |theta| <= pi |v| dt is not empty and 1 / sinc_h stays finite on it).
bool design_band_is_valid(double velocity, double dt);

// The sinc code: gain k is the real part of the Fourier coefficient
//   (1 / 2 pi) int_{|theta| <= pi |v| dt} exp(i theta (k - c)) / sinc_h(theta) d theta,
// c = floor(L / 2), normalized so that max |alpha_k| = 1. Its |K| is flat on
// the band (up to the truncation to L gains). Throws a usage fss::Error unless
// length >= 1 and design_band_is_valid(velocity, dt).
std::vector<double> generate_sinc_code(int length, double velocity, double dt);

// The motion-invariant (MIP) code: target T(theta) = sqrt(pi / |theta|)
// exp(-i pi / 4 sign theta), time origin t0 = c, so gain k is the real part of
//   (1 / 2 pi) int_{|theta| <= pi |v| dt} T(theta) exp(i theta (k - c + 1/2)) / sinc_h(theta),
// normalized so that max |alpha_k| = 1. The 1 / sqrt(theta) singularity is
// removed exactly by the substitution theta = u^2. Same errors as above.
std::vector<double> generate_mip_code(int length, double velocity, double dt);

// Independent uniform gains on [-1, 1) (numerical) or [0, 1) (analog) from a
// generator seeded with `seed`; the same seed gives the same code everywhere.
std::vector<double> generate_random_code(int length, std::uint64_t seed, bool analog);

std::vector<double> snapshot_code(int length);      // (1, 0, ..., 0)
std::vector<double> accumulation_code(int length);  // (1, ..., 1)

struct GenerateOptions {
  CodeFamily family = CodeFamily::kSinc;
  int length = 52;                    // 1 <= L <= kMaxGeneratedCodeLength
  double velocity_px_per_slot = 1.0;  // sinc and mip only: the band they are designed for
  double dt = 1.0;                    // > 0; sinc and mip only
  std::uint64_t seed = 0;             // random only
  bool analog = false;                // random only: gains in [0, 1) instead of [-1, 1)

  // False, with a message naming the field, its value and the rule.
  bool IsValid(std::string* error) const;
};

// The code of `options.family`, named "<family>-L<length>". Throws a usage
// fss::Error when the options are not valid.
ShutterCode generate_code(const GenerateOptions& options);

// ---------------------------------------------------------------------------
// Analysis.

// Mean of 1 / |K(xi)|^2 over xi in [-pi, pi] by the midpoint rule with
// `grid_points` nodes on [0, pi]; infinite if K vanishes at a node.
double band_mean_inverse_power(std::span<const double> gains, double velocity, double dt,
                               int grid_points = kBandGridPoints);

// Cauchy-Schwarz lower bound on Q M for every numerical code of every length
// at this velocity and slot (see README, "Designing codes"):
//   Q M >= (int_{-pi}^{pi} sqrt(w(theta)) d theta)^2 / (4 pi a dt),  a = pi |v| dt,
//   w(theta) = sum over integers m with |theta + 2 pi m| <= a of 1 / sinc_h(theta + 2 pi m)^2.
// For |v| dt = 1 it is (4 G / pi)^2 / dt = 1.36011 / dt (G Catalan's constant).
// It holds for analog codes too (there sum alpha >= sum alpha^2). Infinite for
// |v| dt >= 2, where every code has K = 0 on the band; 0 for v = 0.
double noise_figure_lower_bound(double velocity, double dt);

struct CodeAnalysis {
  int length = 0;
  ShutterMode mode = ShutterMode::kNumerical;
  double velocity = 1.0;
  double dt = 1.0;
  double snr = 100.0;
  int grid = 0;  // 0: midpoint rule with kBandGridPoints nodes; N > 0: the N-point DFT grid

  double sum = 0.0;            // sum alpha_k
  double square_sum = 0.0;     // sum alpha_k^2
  double normalized_l1 = 0.0;  // ||alpha||_1 / sup |alpha|
  double k0 = 0.0;             // K(0) = dt sum alpha_k
  double min_abs = 0.0;        // min |K| on [-pi, pi] (fss::analyze_kernel)
  double min_abs_xi = 0.0;     // where (the non-negative one of a +/- pair)
  bool invertible = false;

  double q = 0.0;                      // Q
  double m = 0.0;                      // M on the grid; infinite when not invertible
  double noise_figure = 0.0;           // Q M
  double snr_level100 = 0.0;           // snr / sqrt(Q M); 0 when not invertible
  double snapshot_snr_level100 = 0.0;  // the snapshot (1, 0, ...) at the same v, dt, grid
  double ratio_to_snapshot = 0.0;      // snr_level100 / snapshot_snr_level100
  double snr_level100_bound = 0.0;     // snr / sqrt(noise_figure_lower_bound(v, dt))
};

// Analyses `gains` at the given velocity, slot, snr and mode; `grid` as in
// CodeAnalysis (pass the simulator's mirror width 2 Wa to get exactly its M).
// Throws a usage fss::Error for an empty or all-zero code, analog gains
// outside [0, 1], a non-finite velocity, dt <= 0, snr <= 0 or grid < 0.
CodeAnalysis analyze_code(std::span<const double> gains, double velocity, double dt, double snr,
                          ShutterMode mode, int grid = 0);

// ---------------------------------------------------------------------------
// Optimization.

// Q M of a code of fixed length on a midpoint band grid, with its gradient.
// K is linear in alpha, K(xi_j) = sum_k alpha_k E_jk with
// E_jk = dt sinc_h(theta_j) exp(-i theta_j (k + 1/2)), so
//   dM / d alpha_k = -(2 / G) sum_j Re(conj(K_j) E_jk) / |K_j|^4,
//   dQ / d alpha_k = 2 dt alpha_k (numerical) or dt (analog).
class NoiseFigure {
 public:
  NoiseFigure(int length, double velocity, double dt, ShutterMode mode,
              int grid_points = kBandGridPoints);

  int length() const { return length_; }

  // Q M of `gains` (length() values); +infinity when K vanishes at a node or
  // Q <= 0. When `gradient` is not empty (length() values) it receives
  // d(Q M) / d alpha (left unspecified for an infinite value).
  double Evaluate(std::span<const double> gains, std::span<double> gradient = {}) const;

 private:
  int length_;
  int grid_;
  double dt_;
  ShutterMode mode_;
  std::vector<double> basis_re_;  // E_jk, row k holds the grid_ nodes j
  std::vector<double> basis_im_;
};

struct OptimizeOptions {
  int length = 52;                    // 1 <= L <= kMaxOptimizedCodeLength
  double velocity_px_per_slot = 1.0;  // 0 < |v| dt < 2
  double dt = 1.0;                    // > 0
  double snr = 100.0;                 // > 0; scales the reported SNR only
  ShutterMode mode = ShutterMode::kNumerical;
  // Gains in {0, 1} (Agrawal-Raskar's search space); then Q is the same in
  // both modes.
  bool binary = false;
  // Light budget: analog or binary codes must let in at least this much light,
  // sum alpha_k >= min_light_slots (in slots of full light; the snapshot lets
  // in 1, Agrawal-Raskar's code 26). 0 means no constraint; at most length.
  double min_light_slots = 0.0;
  // Random starting codes, besides the deterministic ones (the snapshot, and
  // the sinc code for numerical gains). Seeded by `seed`.
  int restarts = 24;
  std::uint64_t seed = 0;
  // Per start: quasi-Newton iterations (continuous gains) or moves (binary).
  int max_iterations = 300;
  // Midpoint nodes on [0, pi] of the objective's band grid.
  int grid_points = 2048;

  // False, with a message naming the field, its value and the rule.
  bool IsValid(std::string* error) const;
};

struct OptimizationResult {
  OptimizeOptions options;
  // The best code found: numerical codes are scaled to max |alpha| = 1
  // (which changes nothing), analog ones to max alpha = 1 (which can only help).
  std::vector<double> gains;
  CodeAnalysis analysis;  // of `gains`, at the options' v, dt, snr, mode, default grid
  int starts = 0;         // starting codes tried
  int best_start = 0;     // index of the start that gave the best code (0: snapshot)
  int iterations = 0;     // iterations or moves over all starts
  int evaluations = 0;    // objective evaluations over all starts

  // Human-readable summary.
  std::string FullReport() const;
};

// Minimizes Q M, i.e. maximizes SNR_100, under the constraints of the mode:
// any real gains (numerical), gains in [0, 1] (analog), gains in {0, 1}
// (binary), and sum alpha >= min_light_slots. Continuous gains: projected
// L-BFGS on log(Q M) from each start. Binary gains: steepest-descent local
// search over single bit flips, and swaps of a 1 with a 0 when no flip helps,
// from each start. The run is bounded by iterations, not time, and depends
// only on the options. Throws a usage fss::Error when the options are not
// valid.
OptimizationResult optimize_code(const OptimizeOptions& options);

}  // namespace fss
