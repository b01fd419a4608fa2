// Tests of fss/kernel.h: invertibility of a code's transfer function and the
// noise amplification M of the inverse filter (docs/method.md §6).

#include "fss/model/kernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fss/model/code.h"
#include "fss/model/transfer.h"

namespace fss {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<double> code_gains(const std::string& name) { return builtin_code(name)->gains; }

// |K(xi)| written out from docs/method.md §1, independently of the library.
double direct_abs_k(const std::vector<double>& gains, double velocity, double dt, double xi) {
  const double theta = xi * velocity * dt;
  const double sinc = theta == 0.0 ? 1.0 : std::sin(theta / 2.0) / (theta / 2.0);
  std::complex<double> sum = 0.0;
  for (std::size_t k = 0; k < gains.size(); ++k) {
    sum += gains[k] * std::polar(1.0, -theta * (static_cast<double>(k) + 0.5));
  }
  return std::abs(dt * sinc * sum);
}

struct ScanMinimum {
  double value = std::numeric_limits<double>::infinity();
  double xi = 0.0;
};

// Minimum of |K| over `points` equally spaced xi in [-pi, pi].
ScanMinimum brute_force_minimum(const std::vector<double>& gains, double velocity, double dt,
                                int points) {
  ScanMinimum best;
  for (int j = 0; j < points; ++j) {
    const double xi = -kPi + 2.0 * kPi * j / (points - 1);
    const double value = direct_abs_k(gains, velocity, dt, xi);
    if (value < best.value) {
      best.value = value;
      best.xi = xi;
    }
  }
  return best;
}

TEST(AnalyzeKernel, RaskarAtUnitVelocityIsInvertible) {
  const auto gains = code_gains("raskar");
  const KernelAnalysis analysis = analyze_kernel(gains, 1.0, 1.0);
  EXPECT_TRUE(analysis.invertible);
  // K(0) = dt * sum alpha = 26 (the code has 26 ones).
  EXPECT_DOUBLE_EQ(analysis.k0, 26.0);
  const ScanMinimum scan = brute_force_minimum(gains, 1.0, 1.0, 200001);
  // A grid step of 3e-5 misses the true minimum by at most |K''| step^2 / 8,
  // well below 1e-6 for |K''| <= 52^2 * 26.
  EXPECT_NEAR(analysis.min_abs, scan.value, 1e-6);
  // The refined minimum is no larger than any sample (slack: rounding of the
  // 52-term sum, ~1e-14).
  EXPECT_LE(analysis.min_abs, scan.value + 1e-13);
  // It is reached where the library says, and on the non-negative side.
  EXPECT_GE(analysis.min_abs_xi, 0.0);
  EXPECT_LE(analysis.min_abs_xi, kPi);
  // Rounding of the 52-term sum at the reported abscissa.
  EXPECT_NEAR(direct_abs_k(gains, 1.0, 1.0, analysis.min_abs_xi), analysis.min_abs, 1e-12);
  EXPECT_GT(analysis.min_abs, kInvertibilityTolerance * 26.0);
}

TEST(AnalyzeKernel, OtherPaperCodesMatchBruteForce) {
  for (const std::string name : {"random", "mip", "sinc"}) {
    const auto gains = code_gains(name);
    const KernelAnalysis analysis = analyze_kernel(gains, 1.0, 1.0);
    EXPECT_TRUE(analysis.invertible) << name;
    const ScanMinimum scan = brute_force_minimum(gains, 1.0, 1.0, 200001);
    // Grid error of the brute-force scan (see above).
    EXPECT_NEAR(analysis.min_abs, scan.value, 1e-6) << name;
    // Rounding of the 52-term sum.
    EXPECT_LE(analysis.min_abs, scan.value + 1e-13) << name;
  }
}

TEST(AnalyzeKernel, AccumulationAtUnitVelocityIsNotInvertible) {
  const auto gains = code_gains("accumulation");
  const KernelAnalysis analysis = analyze_kernel(gains, 1.0, 1.0);
  EXPECT_FALSE(analysis.invertible);
  EXPECT_DOUBLE_EQ(analysis.k0, 52.0);
  // K has exact zeros at xi = 2 pi m / 52; a refined search lands on one.
  EXPECT_LT(analysis.min_abs, 1e-8);
  const double spacing = 2.0 * kPi / 52.0;
  const double m = std::round(analysis.min_abs_xi / spacing);
  EXPECT_GE(m, 1.0);
  // The golden-section search brackets the zero far more tightly than this.
  EXPECT_NEAR(analysis.min_abs_xi, m * spacing, 1e-6);
}

TEST(AnalyzeKernel, ZeroBetweenScanSamplesIsFound) {
  // Accumulation of length 7 at v = 0.9: zeros at xi = 2 pi m / (7 * 0.9),
  // which are not grid points of any uniform scan of [0, pi] with a round
  // number of intervals.
  const std::vector<double> gains(7, 1.0);
  const KernelAnalysis analysis = analyze_kernel(gains, 0.9, 1.0);
  EXPECT_FALSE(analysis.invertible);
  EXPECT_LT(analysis.min_abs, 1e-8);
  const double spacing = 2.0 * kPi / (7.0 * 0.9);
  const double m = std::round(analysis.min_abs_xi / spacing);
  EXPECT_GE(m, 1.0);
  EXPECT_NEAR(analysis.min_abs_xi, m * spacing, 1e-6);  // golden section is much tighter
}

TEST(AnalyzeKernel, SnapshotMinimumIsAtTheBandEdge) {
  const auto gains = code_gains("snapshot");
  const KernelAnalysis analysis = analyze_kernel(gains, 1.0, 1.0);
  EXPECT_TRUE(analysis.invertible);
  EXPECT_DOUBLE_EQ(analysis.k0, 1.0);
  // |K| = |sinc_h(xi)| decreases on [0, pi]: min 2/pi at pi.
  EXPECT_NEAR(analysis.min_abs, 2.0 / kPi, 1e-12);  // rounding of sin
  EXPECT_NEAR(analysis.min_abs, std::abs(sinc_h(kPi)), 1e-12);
  // |K'| at pi is 2/pi^2 ~ 0.2, so a 1e-6 error in |K| allows ~5e-6 in xi.
  EXPECT_NEAR(analysis.min_abs_xi, kPi, 1e-5);
}

TEST(AnalyzeKernel, DtScalesK) {
  const auto gains = code_gains("raskar");
  const KernelAnalysis unit = analyze_kernel(gains, 1.0, 1.0);
  // v = 2, dt = 0.5: same theta = xi, K halved.
  const KernelAnalysis half = analyze_kernel(gains, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(half.k0, 13.0);
  EXPECT_NEAR(half.min_abs, 0.5 * unit.min_abs, 1e-9);  // two independent refinements
  EXPECT_EQ(half.invertible, unit.invertible);
}

TEST(AnalyzeKernel, ZeroVelocityIsConstantK) {
  for (const double dt : {1.0, 0.5, 2.0}) {
    const auto gains = code_gains("raskar");
    const KernelAnalysis analysis = analyze_kernel(gains, 0.0, dt);
    EXPECT_TRUE(analysis.invertible);
    EXPECT_DOUBLE_EQ(analysis.k0, 26.0 * dt);
    // K is the constant dt * sum alpha on the whole band.
    EXPECT_DOUBLE_EQ(analysis.min_abs, 26.0 * dt);
  }
  const std::vector<double> negative = {-0.5, -1.0, 0.25};
  const KernelAnalysis analysis = analyze_kernel(negative, 0.0, 1.0);
  EXPECT_TRUE(analysis.invertible);
  EXPECT_DOUBLE_EQ(analysis.k0, -1.25);
  EXPECT_DOUBLE_EQ(analysis.min_abs, 1.25);
}

TEST(AnalyzeKernel, ZeroSumAtZeroVelocityIsNotInvertible) {
  const std::vector<double> gains = {1.0, -1.0};
  const KernelAnalysis analysis = analyze_kernel(gains, 0.0, 1.0);
  EXPECT_FALSE(analysis.invertible);
  EXPECT_EQ(analysis.k0, 0.0);
  EXPECT_EQ(analysis.min_abs, 0.0);
}

TEST(AnalyzeKernel, ZeroSumCodeIsNotInvertibleInMotion) {
  // K(0) = dt * (1 - 1) = 0 at any velocity.
  const std::vector<double> gains = {1.0, -1.0};
  for (const double v : {1.0, -0.5, 1.7}) {
    const KernelAnalysis analysis = analyze_kernel(gains, v, 1.0);
    EXPECT_FALSE(analysis.invertible) << v;
    EXPECT_EQ(analysis.k0, 0.0);
    EXPECT_LT(analysis.min_abs, 1e-12) << v;  // |K(0)| is exactly 0; rounding only
    EXPECT_NEAR(analysis.min_abs_xi, 0.0, 1e-6) << v;
  }
}

TEST(AnalyzeKernel, AllZeroCodeIsNotInvertible) {
  const std::vector<double> gains(52, 0.0);
  const KernelAnalysis analysis = analyze_kernel(gains, 1.0, 1.0);
  EXPECT_FALSE(analysis.invertible);
  EXPECT_EQ(analysis.k0, 0.0);
  EXPECT_EQ(analysis.min_abs, 0.0);
}

// M written out from its definition, with the independent |K|.
double direct_mean_inverse_power(const std::vector<double>& gains, double v, double dt, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const int f = 2 * i < n ? i : i - n;
    const double k = direct_abs_k(gains, v, dt, 2.0 * kPi * f / n);
    sum += 1.0 / (k * k);
  }
  return sum / n;
}

TEST(MeanInversePower, SnapshotAtRestIsOneOverDtSquared) {
  const auto gains = code_gains("snapshot");
  // Powers of two: every step of the mean is exact.
  for (const double dt : {1.0, 0.5, 2.0, 0.125}) {
    for (const int n : {1, 2, 7, 920}) {
      EXPECT_EQ(mean_inverse_power(gains, 0.0, dt, n), 1.0 / (dt * dt)) << dt << " " << n;
    }
  }
  // Other dt: averaging n equal rounded terms costs a few ulps.
  EXPECT_NEAR(mean_inverse_power(gains, 0.0, 0.3, 920), 1.0 / 0.09, 1e-12);
}

TEST(MeanInversePower, MatchesDirectSum) {
  for (const std::string name : {"raskar", "random", "sinc", "snapshot"}) {
    const auto gains = code_gains(name);
    const double expected = direct_mean_inverse_power(gains, 1.0, 1.0, 920);
    // 1/|K|^2 amplifies the relative rounding of K (~1e-14 for raskar's min).
    EXPECT_NEAR(mean_inverse_power(gains, 1.0, 1.0, 920), expected, 1e-9 * expected) << name;
  }
  const auto raskar = code_gains("raskar");
  for (const int n : {51, 52, 460}) {
    const double expected = direct_mean_inverse_power(raskar, -1.0, 0.8, n);
    EXPECT_NEAR(mean_inverse_power(raskar, -1.0, 0.8, n), expected, 1e-9 * expected) << n;
  }
}

TEST(MeanInversePower, InfiniteWhenABinIsZero) {
  // Bin 0 is xi = 0, where K = dt * (1 - 1) = 0 exactly.
  const std::vector<double> gains = {1.0, -1.0};
  for (const int n : {1, 2, 7, 920}) {
    const double m = mean_inverse_power(gains, 1.0, 1.0, n);
    EXPECT_TRUE(std::isinf(m) && m > 0.0) << n << ": " << m;
  }
  const std::vector<double> zeros(5, 0.0);
  const double m = mean_inverse_power(zeros, 1.0, 1.0, 16);
  EXPECT_TRUE(std::isinf(m) && m > 0.0) << m;
}

// The zero rule: |K| <= 1e-12 dt sum |alpha|, relative to the code's scale.
TEST(TransferVanishes, IsRelativeToTheCodesScale) {
  const std::vector<double> raskar = code_gains("raskar");
  EXPECT_EQ(transfer_scale(raskar, 0.5), 13.0);  // 26 ones
  // |v| dt = 2: sinc_h(2 pi) is round-off (about 4e-17), not 0.
  const double nyquist = std::abs(transfer_function(raskar, 2.0, 1.0, -kPi));
  EXPECT_GT(nyquist, 0.0);
  EXPECT_TRUE(transfer_vanishes(nyquist, transfer_scale(raskar, 1.0)));
  EXPECT_FALSE(transfer_vanishes(std::abs(transfer_function(raskar, 1.999, 1.0, -kPi)),
                                 transfer_scale(raskar, 1.0)));
  // The same value on a code a billion times smaller is no zero.
  EXPECT_FALSE(transfer_vanishes(nyquist, 1e-9 * transfer_scale(raskar, 1.0)));
  // sum alpha = 0 does not make the scale 0.
  EXPECT_EQ(transfer_scale(std::vector<double>{1.0, -1.0}, 2.0), 4.0);
  EXPECT_TRUE(transfer_vanishes(0.0, 4.0));
  EXPECT_TRUE(transfer_vanishes(4e-12, 4.0));
  EXPECT_FALSE(transfer_vanishes(4.1e-12, 4.0));
  EXPECT_TRUE(transfer_vanishes(1e-7, 1.0, kInvertibilityTolerance));
}

// M on a grid whose Nyquist bin sits on the zero of sinc_h at |v| dt = 2 is
// infinite, as the restoration leaves that bin out (not 1 / round-off^2).
TEST(MeanInversePower, InfiniteWhenABinVanishesToRoundOff) {
  for (const auto& [velocity, dt] :
       std::vector<std::pair<double, double>>{{2.0, 1.0}, {1.0, 2.0}, {4.0, 0.5}, {-2.0, 1.0}}) {
    const double m = mean_inverse_power(code_gains("raskar"), velocity, dt, 920);
    EXPECT_TRUE(std::isinf(m)) << velocity << " " << dt << ": " << m;
  }
  EXPECT_TRUE(std::isfinite(mean_inverse_power(code_gains("raskar"), 1.999, 1.0, 920)));
}

TEST(MeanInversePower, AccumulationOnItsZerosGrid) {
  // n = 52: bin 1 is xi = 2 pi / 52, a zero of the accumulation code. It may
  // be a tiny rounding residue rather than exactly 0, so M is either infinite
  // or enormous.
  const double m = mean_inverse_power(code_gains("accumulation"), 1.0, 1.0, 52);
  EXPECT_GT(m, 1e20);
}

}  // namespace
}  // namespace fss
