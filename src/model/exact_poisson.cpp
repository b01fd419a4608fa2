// The exact Poisson sampler (exact_poisson.h). Compiled with the samplers'
// flags (CMakeLists.txt): no contraction into fused multiply-adds, so the
// arithmetic's bits do not depend on the processor.
#include "model/exact_poisson.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "core/vectorize.h"
#include "model/bounded_log.h"

namespace fss {

namespace {

// ln k! for k < kLogFactorialTable, from lgamma once.
constexpr int kLogFactorialTable = 64;
const std::array<double, kLogFactorialTable> kLogFactorial = []() noexcept {
  std::array<double, kLogFactorialTable> table{};
  for (int k = 0; k < kLogFactorialTable; ++k) table[k] = std::lgamma(k + 1.0);
  return table;
}();

// Stirling's correction, from r = 1 / k: delta(k) = ln k! - (k ln k - k + ln(2 pi k) / 2)
//   = 1 / (12 k) - 1 / (360 k^3) + 1 / (1260 k^5) - 1 / (1680 k^7) + ...,
// the omitted terms below 1 / (1188 k^9) < 3e-20 for k >= kLogFactorialTable.
double stirling_correction_of_inverse(double r) {  // r = 1 / k
  const double r2 = r * r;
  return r * (1.0 / 12.0 - r2 * (1.0 / 360.0 - r2 * (1.0 / 1260.0 - r2 * (1.0 / 1680.0))));
}

// Inversion: the smallest k with U < F(k), F the distribution function summed
// from p(0) = exp(-mean) by p(k) = p(k - 1) mean / k. The search stops at
// kInversionCap (P(X >= 100) < 1e-60 for mean < 10): a uniform beyond the
// rounded F's top is drawn again.
constexpr int kInversionCap = 100;
constexpr double kLargestFinite = std::numeric_limits<double>::max();
constexpr double kSmallestNormal = std::numeric_limits<double>::min();
constexpr std::array<double, kInversionCap> kInverse = [] {
  std::array<double, kInversionCap> table{};  // 1 / k, correctly rounded by the compiler
  for (int k = 1; k < kInversionCap; ++k) table[k] = 1.0 / k;
  return table;
}();

// Inversion from the uniform u, then from the stream's should u lie beyond
// the rounded F's top.
double inversion(double mean, double u, RandomStream& stream) {
  const double p0 = std::exp(-mean);
  for (;;) {
    double p = p0;
    double cdf = p0;
    int k = 0;
    while (u >= cdf && k + 1 < kInversionCap) {
      ++k;
      p *= mean * kInverse[k];
      cdf += p;
    }
    if (u < cdf) return k;
    u = stream.uniform();
  }
}

// PTRS, Hörmann (1993), "The transformed rejection method for generating
// Poisson random variables", for mean >= 10: with U uniform on [-1/2, 1/2),
// V on (0, 1] and u_s = 1/2 - |U|, the candidate
//   k = floor((2 a / u_s + b) U + mean + 0.43),
//   b = 0.931 + 2.53 sqrt(mean),  a = -0.059 + 0.02483 b,
// is accepted at once when u_s >= 0.07 and V <= v_r = 0.9277 - 3.6224 / (b - 2),
// rejected when k < 0 or (u_s < 0.013 and V > u_s), and otherwise accepted when
//   ln(V alpha / (a / u_s^2 + b)) <= ln P(X = k),  alpha = 1.1239 + 1.1328 / (b - 3.4).
// Inline, so that the row's first tries vectorize.
struct Ptrs {
  double b, a, v_r;
  explicit Ptrs(double mean)
      : b(0.931 + 2.53 * std::sqrt(mean)),
        a(-0.059 + 0.02483 * b),
        v_r(0.9277 - 3.6224 / (b - 2.0)) {}
  double candidate(double mean, double u, double u_s) const {
    return std::floor((2.0 * a / u_s + b) * u + mean + 0.43);  // u_s = 0 gives -inf
  }
  bool quick_accept(double u_s, double v) const { return u_s >= 0.07 && v <= v_r; }
  // Rejected at once: k < 0, or u_s < 0.013 and V > u_s (& and |: no branch, for the bulk test).
  static bool rejects(double u_s, double v, double k) {
    return (k < 0.0) | ((u_s < 0.013) & (v > u_s));
  }
  // V alpha / (a / u_s^2 + b) = V alpha u_s^2 / (a + b u_s^2), the test's left side but for
  // sqrt(2 pi k) above the table.
  double ratio(double u_s, double v) const {
    const double alpha = 1.1239 + 1.1328 / (b - 3.4);
    const double u_s2 = u_s * u_s;
    return v * alpha * u_s2 / (a + b * u_s2);
  }
  // The rest of a try that quick_accept did not accept. With
  // V alpha / (a / u_s^2 + b) = V alpha u_s^2 / (a + b u_s^2) and, for
  // k >= kLogFactorialTable, ln P(X = k) = (k - mean) + k log1p((mean - k) / k)
  // - ln(2 pi k) / 2 - delta(k) (poisson_log_pmf), the test for those k is
  //   ln(V alpha u_s^2 sqrt(2 pi k) / (a + b u_s^2)) <= (k - mean) + k log1p((mean - k) r) - delta,
  // r = 1 / k: one logarithm and one log1p.
  bool accepts(double mean, double u_s, double v, double k) const {
    if (rejects(u_s, v, k)) return false;
    const double ratio = this->ratio(u_s, v);
    if (k < kLogFactorialTable) return std::log(ratio) <= poisson_log_pmf(k, mean);
    const double r = 1.0 / k;
    return std::log(ratio * std::sqrt(2.0 * std::numbers::pi * k)) <=
           (k - mean) + k * std::log1p((mean - k) * r) - stirling_correction_of_inverse(r);
  }
};

// PTRS's tries from (u, v) on: u uniform on [0, 1), v on (0, 1].
double transformed_rejection(double mean, double u, double v, RandomStream& stream) {
  const Ptrs ptrs(mean);
  for (;;) {
    const double centred = u - 0.5;
    const double u_s = 0.5 - std::abs(centred);
    const double k = ptrs.candidate(mean, centred, u_s);
    if (ptrs.quick_accept(u_s, v) || ptrs.accepts(mean, u_s, v, k)) return k;
    u = stream.uniform();
    v = stream.uniform_open_zero();
  }
}

// The variate for a first pair of uniforms (u on [0, 1), v on (0, 1]; v is
// unused below kInversionLimit), later ones from the stream.
double variate_from(double mean, double u, double v, RandomStream& stream) {
  if (!(mean > 0.0)) return 0.0;
  if (!std::isfinite(mean)) return mean;
  return mean < kInversionLimit ? inversion(mean, u, stream)
                                : transformed_rejection(mean, u, v, stream);
}

// RandomStream's conversions of a 64-bit output (noise_stream.h).
inline double to_uniform(std::uint64_t word) {
  return static_cast<double>(static_cast<std::int64_t>(word >> 11)) * 0x1.0p-53;
}
inline double to_uniform_open_zero(std::uint64_t word) {
  return static_cast<double>(static_cast<std::int64_t>((word >> 11) + 1)) * 0x1.0p-53;
}

}  // namespace

double poisson_log_pmf(double k, double mean) {
  if (k < kLogFactorialTable) {
    return -mean + k * std::log(mean) - kLogFactorial[static_cast<int>(k)];
  }
  // ln P = (k - mean) + k ln(mean / k) - ln(2 pi k) / 2 - delta(k), with
  // ln(mean / k) = log1p((mean - k) / k): no cancellation of large terms.
  return (k - mean) + k * std::log1p((mean - k) / k) - 0.5 * std::log(2.0 * std::numbers::pi * k) -
         stirling_correction_of_inverse(1.0 / k);
}

double exact_poisson_variate(double mean, RandomStream& stream) {
  if (!(mean > 0.0) || !std::isfinite(mean)) return variate_from(mean, 0.0, 1.0, stream);
  const double u = stream.uniform();
  const double v = mean < kInversionLimit ? 1.0 : stream.uniform_open_zero();
  return variate_from(mean, u, v, stream);
}

namespace {

// A first try's slow test, decided in bulk: the candidates `count` of them
// (compacted from a block), their decision 1 (accept), 0 (reject) or -1
// (too close to call: the exact scalar test decides).
struct FirstTries {
  static constexpr std::size_t kSize = 256;
  std::array<double, kSize> mean, u_s, v, k, log_factorial;
  std::array<std::uint32_t, kSize> pixel;  // index in the block
  std::array<double, kSize> decision;
  std::size_t count = 0;
  // Every pixel not settled, in pixel order (those above and the others).
  std::array<std::uint32_t, kSize> unsettled;
  std::size_t unsettled_count = 0;
};

// Ptrs::accepts(mean, u_s, v, k) by the bounded logarithms (log_factorial: ln k! for k below
// kLogFactorialTable): 1 accept, 0 reject, -1 too close to call. Both sides err by less than
// 1e-12 S, S = 1 + |ln(...)| + the magnitudes summed on the right, while the double arithmetic
// of accepts() errs by a few ulps of S: with a margin of 1e-9 S, the decision is accepts()'s
// wherever it is taken. Selections on bools combined by & and |, no branch: it vectorizes.
[[gnu::always_inline]] inline double first_try_decision(double mean, double u_s, double v, double k,
                                                        double log_factorial) {
  const Ptrs ptrs(mean);
  const double ratio = ptrs.ratio(u_s, v);
  const bool table = k < kLogFactorialTable;
  const double r = 1.0 / k;
  const double t = (mean - k) * r;
  const double lhs = bounded_log(table ? ratio : ratio * std::sqrt(2.0 * std::numbers::pi * k));
  // ln(mean) for the table's k, else ln(1 + t) (bounded_log1p's two ways)
  const double second_log = bounded_log(table ? mean : 1.0 + t);
  const double log1p_t = std::abs(t) <= 0.25 ? bounded_log1p_small(t) : second_log;
  const double rhs = table ? -mean + k * second_log - log_factorial
                           : (k - mean) + k * log1p_t - stirling_correction_of_inverse(r);
  const double scale = 1.0 + std::abs(lhs) + mean + std::abs(k - mean) +
                       k * std::abs(table ? second_log : log1p_t) + log_factorial;
  const double margin = 1e-9 * scale;
  const bool rejected = Ptrs::rejects(u_s, v, k);
  const bool normal = ratio >= kSmallestNormal;  // bounded_log's domain
  double sure = -1.0;
  sure = (normal & (lhs - margin > rhs)) ? 0.0 : sure;
  sure = (normal & (lhs + margin < rhs)) ? 1.0 : sure;
  return rejected ? 0.0 : sure;
}

// first_try_decision for each of the tries.
void decide_first_tries(FirstTries& tries) {
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict mu = tries.mean.data();
    const double* __restrict us = tries.u_s.data();
    const double* __restrict vs = tries.v.data();
    const double* __restrict ks = tries.k.data();
    const double* __restrict log_factorial = tries.log_factorial.data();
    double* __restrict decision = tries.decision.data();
    const std::size_t count = tries.count;
    for (std::size_t i = 0; i < count; ++i) {
      decision[i] = first_try_decision(mu[i], us[i], vs[i], ks[i], log_factorial[i]);
    }
  });
}

// A block's first tries: the candidate k and u_s of each pixel, and
// value[i] = k where the quick acceptance settles it, -1 elsewhere.
struct BlockTries {
  static constexpr std::size_t kSize = FirstTries::kSize;
  std::array<double, kSize> u, v, k, u_s, value;
};

// PTRS's first tries with their quick acceptance, for a block at once: a
// function of restrict parameters, so that GCC knows the arrays apart and
// vectorizes the loop.
[[gnu::always_inline]] inline void quick_first_tries_kernel(
    std::size_t count, const double* __restrict mu, const double* __restrict us,
    const double* __restrict vs, double* __restrict ks, double* __restrict shifted,
    double* __restrict settled) {
  for (std::size_t i = 0; i < count; ++i) {
    const Ptrs ptrs(mu[i]);
    const double centred = us[i] - 0.5;
    const double u_s = 0.5 - std::abs(centred);
    const double k = ptrs.candidate(mu[i], centred, u_s);
    const bool quick =
        mu[i] >= kInversionLimit && mu[i] <= kLargestFinite && ptrs.quick_accept(u_s, vs[i]);
    ks[i] = k;
    shifted[i] = u_s;
    settled[i] = quick ? k : -1.0;  // -1: not settled
  }
}

void quick_first_tries(std::span<const double> mean, BlockTries& block) {
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    quick_first_tries_kernel(mean.size(), mean.data(), block.u.data(), block.v.data(),
                             block.k.data(), block.u_s.data(), block.value.data());
  });
}

// The block's pixels not settled by the quick acceptance (value -1), listed
// in pixel order; with `bulk`, those of means the bulk test takes (PTRS's
// below 2^40, where every term of the test stays far from overflow) also
// compacted into `tries` and decided.
void decide_unsettled(std::span<const double> mean, const BlockTries& block, FirstTries& tries,
                      bool bulk) {
  const auto taken = [&](std::size_t i) {
    return static_cast<int>(mean[i] >= kInversionLimit) & static_cast<int>(mean[i] < 0x1.0p40);
  };
  std::size_t unsettled = 0;
  std::size_t takes = 0;
  for (std::size_t i = 0; i < mean.size(); ++i) {  // without branches: every pixel written
    const bool open = block.value[i] < 0.0;
    tries.unsettled[unsettled] = static_cast<std::uint32_t>(i);
    unsettled += open ? 1 : 0;
    takes += (static_cast<int>(open) & taken(i)) != 0 ? 1 : 0;
  }
  std::size_t count = 0;
  for (std::size_t j = 0; bulk && takes > 0 && j < unsettled; ++j) {  // the same, compacted
    const std::size_t i = tries.unsettled[j];
    const double k = block.k[i];
    const bool table = (k >= 0.0) & (k < kLogFactorialTable);
    tries.mean[count] = mean[i];
    tries.u_s[count] = block.u_s[i];
    tries.v[count] = block.v[i];
    tries.k[count] = k;
    tries.log_factorial[count] = kLogFactorial[table ? static_cast<std::size_t>(k) : 0];
    tries.pixel[count] = static_cast<std::uint32_t>(i);
    count += taken(i) != 0 ? 1 : 0;
  }
  tries.unsettled_count = unsettled;
  tries.count = count;
  if (count > 0) decide_first_tries(tries);
}

// add_exact_poisson_row, its unsettled first tries decided in bulk or not.
void add_row(std::span<const double> mean, RandomStream& stream, double scale,
             std::span<double> out, bool bulk) {
  // Blocks of kBlock pixels: two uniforms a pixel in pixel order, PTRS's
  // first tries with their quick acceptance for the whole block at once
  // (vectorized), their slow tests in bulk (vectorized), then, in pixel
  // order, every pixel they did not settle.
  constexpr std::size_t kBlock = FirstTries::kSize;
  BlockTries block_tries;
  FirstTries tries;
  std::array<double, kBlock>& value = block_tries.value;
  for (std::size_t start = 0; start < mean.size(); start += kBlock) {
    const std::size_t m = std::min(kBlock, mean.size() - start);
    const std::span<const double> block = mean.subspan(start, m);
    for (std::size_t i = 0; i < m; ++i) {
      block_tries.u[i] = to_uniform(stream.next());
      block_tries.v[i] = to_uniform_open_zero(stream.next());
    }
    quick_first_tries(block, block_tries);
    decide_unsettled(block, block_tries, tries, bulk);
    std::size_t next = 0;                                      // the next decided try
    for (std::size_t j = 0; j < tries.unsettled_count; ++j) {  // in pixel order
      const std::size_t i = tries.unsettled[j];
      const bool decided = next < tries.count && tries.pixel[next] == i;
      const double decision = decided ? tries.decision[next++] : -1.0;
      if (decision > 0.0) {
        value[i] = block_tries.k[i];
      } else if (decision == 0.0) {  // rejected: PTRS's next tries
        const double u = stream.uniform();
        const double v = stream.uniform_open_zero();
        value[i] = transformed_rejection(block[i], u, v, stream);
      } else {
        value[i] = variate_from(block[i], block_tries.u[i], block_tries.v[i], stream);
      }
    }
    for (std::size_t i = 0; i < m; ++i) out[start + i] += scale * value[i];
  }
}

}  // namespace

void add_exact_poisson_row(std::span<const double> mean, RandomStream& stream, double scale,
                           std::span<double> out) {
  add_row(mean, stream, scale, out, /*bulk=*/true);
}

void add_exact_poisson_row_scalar(std::span<const double> mean, RandomStream& stream, double scale,
                                  std::span<double> out) {
  add_row(mean, stream, scale, out, /*bulk=*/false);
}

}  // namespace fss
