// Tests of fss/transfer.h: sinc_h, the transfer function K of a code (docs/method.md §1),
// the DFT bin layout and K on the bins.

#include "fss/model/transfer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include "fss/model/code.h"
#include "support/test_util.h"

namespace fss {
namespace {

constexpr double kPi = 3.14159265358979323846;

// |a - b| <= tolerance, for complex values.
::testing::AssertionResult ComplexNear(Complex a, Complex b, double tolerance) {
  if (std::abs(a - b) <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << a << " vs " << b << ": |difference| " << std::abs(a - b) << " > " << tolerance;
}

std::vector<double> code_gains(const std::string& name) { return builtin_code(name)->gains; }

double abs_sum(const std::vector<double>& gains) {
  double s = 0.0;
  for (const double g : gains) s += std::abs(g);
  return s;
}

// Frequencies spread over and beyond the band, avoiding the special points.
const std::vector<double> kXis = {-3.0, -2.2, -1.0, -0.37, -1e-7, 0.013, 0.5, 1.234, 2.0, 2.9, 3.1};

TEST(SincH, ValueAtZeroIsOne) { EXPECT_EQ(sinc_h(0.0), 1.0); }

TEST(SincH, KnownValues) {
  // sinc_h(pi) = sin(pi/2) / (pi/2) = 2/pi; zeros at 2 pi m.
  EXPECT_NEAR(sinc_h(kPi), 2.0 / kPi, 1e-15);  // a few ulps of libm sin
  EXPECT_NEAR(sinc_h(2.0 * kPi), 0.0, 1e-15);
  EXPECT_NEAR(sinc_h(4.0 * kPi), 0.0, 1e-15);
  EXPECT_NEAR(sinc_h(1.0), std::sin(0.5) / 0.5, 1e-15);
}

TEST(SincH, ContinuousNearZero) {
  // The direct quotient is accurate to a few ulps here, so 1e-15 is a tight
  // check of whatever small-argument branch the library uses.
  for (const double x : {1e-3, 1e-5, 2e-4, 1.9999e-4, 2.0001e-4, 1e-8, 1e-12}) {
    const double direct = std::sin(x / 2.0) / (x / 2.0);
    EXPECT_NEAR(sinc_h(x), direct, 1e-15) << "x = " << x;
    EXPECT_NEAR(sinc_h(-x), direct, 1e-15) << "x = " << -x;
  }
  EXPECT_LT(sinc_h(1e-3), 1.0);
  EXPECT_LE(sinc_h(1e-5), 1.0);
}

TEST(SincH, EvenFunction) {
  for (const double x : {1e-9, 1e-5, 1e-4, 2e-4, 0.3, 1.0, 3.0, 7.5, 100.0}) {
    // sin is odd, so the quotient is even to the last bit; allow 4 ulps.
    EXPECT_DOUBLE_EQ(sinc_h(-x), sinc_h(x)) << "x = " << x;
  }
}

TEST(TransferFunction, ValueAtZeroIsDtTimesSum) {
  for (const std::string name : {"snapshot", "accumulation", "raskar", "random", "mip", "sinc"}) {
    const auto gains = code_gains(name);
    for (const double dt : {1.0, 0.5, 0.37, 3.0}) {
      for (const double v : {1.0, -2.5, 0.0}) {
        const Complex k0 = transfer_function(gains, v, dt, 0.0);
        // Summation order may differ from gain_sum: rounding of 52 terms.
        const double tolerance = 1e-13 * dt * abs_sum(gains);
        EXPECT_NEAR(k0.real(), dt * gain_sum(gains), tolerance) << name << " dt " << dt;
        EXPECT_NEAR(k0.imag(), 0.0, tolerance) << name << " dt " << dt;
      }
    }
  }
}

TEST(TransferFunction, SnapshotClosedForm) {
  const auto gains = code_gains("snapshot");
  for (const double dt : {1.0, 0.25, 1.7}) {
    for (const double v : {1.0, -1.0, 0.6, 2.0}) {
      for (const double xi : kXis) {
        const double theta = xi * v * dt;
        const Complex expected = dt * sinc_h(theta) * std::polar(1.0, -theta / 2.0);
        // A handful of roundings on values of size dt.
        EXPECT_TRUE(ComplexNear(transfer_function(gains, v, dt, xi), expected, 1e-14 * dt))
            << "dt " << dt << " v " << v << " xi " << xi;
      }
    }
  }
}

TEST(TransferFunction, AccumulationIsTheDirichletKernel) {
  for (const int length : {1, 2, 7, 52}) {
    const std::vector<double> gains(static_cast<std::size_t>(length), 1.0);
    for (const double dt : {1.0, 0.3}) {
      for (const double v : {1.0, -0.8, 1.9}) {
        for (const double xi : kXis) {
          const double theta = xi * v * dt;
          const double dirichlet = std::sin(length * theta / 2.0) / std::sin(theta / 2.0);
          const Complex expected =
              dt * sinc_h(theta) * dirichlet * std::polar(1.0, -theta * length / 2.0);
          // Rounding of L terms of size dt, relative to the peak dt L.
          EXPECT_TRUE(
              ComplexNear(transfer_function(gains, v, dt, xi), expected, 1e-12 * dt * length))
              << "L " << length << " dt " << dt << " v " << v << " xi " << xi;
        }
      }
    }
  }
}

TEST(TransferFunction, MatchesTheDefiningSum) {
  // K = dt sinc_h(theta) sum_k alpha_k exp(-i theta (k + 1/2)), term by term.
  for (const std::string name : {"raskar", "random", "mip", "sinc"}) {
    const auto gains = code_gains(name);
    for (const double xi : kXis) {
      const double v = 1.3;
      const double dt = 0.7;
      const double theta = xi * v * dt;
      Complex sum = 0.0;
      for (std::size_t k = 0; k < gains.size(); ++k) {
        sum += gains[k] * std::polar(1.0, -theta * (static_cast<double>(k) + 0.5));
      }
      const Complex expected = dt * sinc_h(theta) * sum;
      // Rounding of 52 terms, relative to dt sum |alpha|.
      EXPECT_TRUE(
          ComplexNear(transfer_function(gains, v, dt, xi), expected, 1e-12 * dt * abs_sum(gains)))
          << name << " xi " << xi;
    }
  }
}

TEST(TransferFunction, ConjugateSymmetry) {
  for (const std::string name : {"raskar", "random", "mip", "sinc", "snapshot"}) {
    const auto gains = code_gains(name);
    for (const double xi : kXis) {
      const Complex plus = transfer_function(gains, 1.0, 1.0, xi);
      const Complex minus = transfer_function(gains, 1.0, 1.0, -xi);
      // Real gains: K(-xi) = conj K(xi) up to rounding of 52 terms.
      EXPECT_TRUE(ComplexNear(minus, std::conj(plus), 1e-13 * abs_sum(gains)))
          << name << " xi " << xi;
    }
  }
}

TEST(TransferFunction, VelocityAndDtEnterThroughThetaAndPrefactor) {
  const auto gains = code_gains("random");
  const double scale = abs_sum(gains);
  for (const double xi : kXis) {
    for (const double v : {1.0, -1.0, 0.45, -1.6, 2.0}) {
      for (const double dt : {1.0, 0.5, 1.25}) {
        // K(xi; v, dt) = dt * K(xi v dt; 1, 1).
        const Complex unit = transfer_function(gains, 1.0, 1.0, xi * v * dt);
        // Rounding of theta = xi v dt in two orders, times |dK/dtheta| <= 52 scale.
        const double tolerance = 1e-12 * dt * scale;
        EXPECT_TRUE(ComplexNear(transfer_function(gains, v, dt, xi), dt * unit, tolerance))
            << "xi " << xi << " v " << v << " dt " << dt;
        // Swapping the roles of xi and v changes nothing either.
        EXPECT_TRUE(ComplexNear(transfer_function(gains, xi, dt, v), dt * unit, tolerance))
            << "xi " << xi << " v " << v << " dt " << dt;
      }
    }
  }
}

TEST(TransferFunction, ZeroVelocityIsConstant) {
  const auto gains = code_gains("mip");
  const Complex k0 = transfer_function(gains, 0.0, 0.8, 0.0);
  for (const double xi : kXis) {
    // theta = 0 exactly whatever xi: the same computation.
    EXPECT_TRUE(ComplexNear(transfer_function(gains, 0.0, 0.8, xi), k0, 1e-15)) << xi;
  }
}

TEST(TransferFunction, LinearInTheGains) {
  const auto a = code_gains("raskar");
  const auto b = code_gains("mip");
  const double ca = 0.75;
  const double cb = -2.5;
  std::vector<double> combined(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) combined[k] = ca * a[k] + cb * b[k];
  for (const double xi : kXis) {
    const Complex expected =
        ca * transfer_function(a, 1.1, 0.9, xi) + cb * transfer_function(b, 1.1, 0.9, xi);
    // Rounding of 52 terms of size up to |ca| + |cb|.
    EXPECT_TRUE(ComplexNear(transfer_function(combined, 1.1, 0.9, xi), expected, 1e-12 * 52 * 3.25))
        << xi;
  }
}

TEST(BinFrequency, EvenLength) {
  // n = 8: bins 0 .. 4 are 0, pi/4, pi/2, 3 pi/4, and the Nyquist bin -pi.
  EXPECT_EQ(bin_frequency(0, 8), 0.0);
  EXPECT_DOUBLE_EQ(bin_frequency(1, 8), kPi / 4.0);
  EXPECT_DOUBLE_EQ(bin_frequency(2, 8), kPi / 2.0);
  EXPECT_DOUBLE_EQ(bin_frequency(3, 8), 3.0 * kPi / 4.0);
  EXPECT_DOUBLE_EQ(bin_frequency(4, 8), -kPi);
  // The rest of the full layout: i - n.
  EXPECT_DOUBLE_EQ(bin_frequency(5, 8), -3.0 * kPi / 4.0);
  EXPECT_DOUBLE_EQ(bin_frequency(7, 8), -kPi / 4.0);
  for (const int n : {2, 6, 10, 920}) {
    EXPECT_DOUBLE_EQ(bin_frequency(n / 2, n), -kPi) << n;
    EXPECT_DOUBLE_EQ(bin_frequency(n / 2 - 1, n), 2.0 * kPi * (n / 2 - 1) / n) << n;
  }
}

TEST(BinFrequency, OddLength) {
  // n = 7: bins 0 .. 3 hold 2 pi i / 7, all positive; 4 .. 6 hold 2 pi (i - 7) / 7.
  for (int i = 0; i <= 3; ++i) EXPECT_DOUBLE_EQ(bin_frequency(i, 7), 2.0 * kPi * i / 7.0) << i;
  for (int i = 4; i < 7; ++i) {
    EXPECT_DOUBLE_EQ(bin_frequency(i, 7), 2.0 * kPi * (i - 7) / 7.0) << i;
  }
  EXPECT_GT(bin_frequency(3, 7), 0.0);
  EXPECT_LT(bin_frequency(3, 7), kPi);
  EXPECT_EQ(bin_frequency(0, 1), 0.0);
}

TEST(TransferFunctionBins, EqualsTransferFunctionAtBinFrequency) {
  for (const int n : {1, 2, 7, 8, 101, 920}) {
    for (const std::string name : {"raskar", "sinc"}) {
      const auto gains = code_gains(name);
      const auto bins = transfer_function_bins(gains, -1.2, 0.8, n);
      ASSERT_EQ(bins.size(), static_cast<std::size_t>(n / 2 + 1)) << n;
      for (int i = 0; i <= n / 2; ++i) {
        const Complex expected = transfer_function(gains, -1.2, 0.8, bin_frequency(i, n));
        // Same definition; allow rounding of a different evaluation order.
        EXPECT_TRUE(ComplexNear(bins[i], expected, 1e-12 * abs_sum(gains)))
            << name << " n " << n << " bin " << i;
      }
    }
  }
}

TEST(SlotTransferFunctionBins, ClosedForm) {
  const int n = 64;
  for (const int k : {0, 5, 51}) {
    const auto bins = slot_transfer_function_bins(k, 0.9, 1.5, n);
    ASSERT_EQ(bins.size(), static_cast<std::size_t>(n / 2 + 1));
    for (int i = 0; i <= n / 2; ++i) {
      const double theta = bin_frequency(i, n) * 0.9 * 1.5;
      const Complex expected = 1.5 * sinc_h(theta) * std::polar(1.0, -theta * (k + 0.5));
      // A few roundings; the phase theta (k + 1/2) is up to ~100 radians.
      EXPECT_TRUE(ComplexNear(bins[i], expected, 1e-13)) << "k " << k << " bin " << i;
    }
  }
}

TEST(SlotTransferFunctionBins, WeightedSumIsTheCodesTransferFunction) {
  for (const int n : {8, 9, 920}) {
    for (const std::string name : {"raskar", "random", "mip"}) {
      const auto gains = code_gains(name);
      const auto expected = transfer_function_bins(gains, 1.0, 1.0, n);
      std::vector<Complex> sum(expected.size(), 0.0);
      for (std::size_t k = 0; k < gains.size(); ++k) {
        const auto slot = slot_transfer_function_bins(static_cast<int>(k), 1.0, 1.0, n);
        ASSERT_EQ(slot.size(), expected.size());
        for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += gains[k] * slot[i];
      }
      for (std::size_t i = 0; i < sum.size(); ++i) {
        // The brief's bound: rounding of 52 unit-size terms is ~1e-14.
        EXPECT_TRUE(ComplexNear(sum[i], expected[i], 1e-12)) << name << " n " << n << " bin " << i;
      }
    }
  }
}

TEST(TransferFunction, MatchesReferenceSpectrumTxt) {
  // "xi |K(xi)|" lines of the reference program for the raskar code, v = 1,
  // dt = 1, both columns printed with 6 significant digits. The reference
  // steps xi in low precision (its "0" line reads 9.65337e-07), so we evaluate
  // at the printed xi, not at -pi + 2 pi j / 100. Tolerance: the printed |K|
  // is off by up to 5e-6 relative, covered by 2e-5 relative + 2e-5 absolute;
  // the printed xi is off by up to half a unit in its 6th digit, and |K|
  // changes by up to ~40 per radian here (~2e-4 over that interval), so the
  // change of |K| across that interval is added. A wrong sinc, gain order
  // interpretation or frequency scale is still off by far more.
  const auto gains = code_gains("raskar");
  auto abs_k = [&](double xi) { return std::abs(transfer_function(gains, 1.0, 1.0, xi)); };
  // |dK/dxi| <= sum |alpha_k| (k + 1/2) + max |sinc_h'| sum |alpha_k|, max |sinc_h'| < 1/4.
  double slope_bound = 0.0;
  for (std::size_t k = 0; k < gains.size(); ++k) {
    slope_bound += std::abs(gains[k]) * (static_cast<double>(k) + 0.5 + 0.25);
  }
  std::istringstream lines(
      test::read_file(test::fixture_path("camera_numerical_raskar_v1_noisefree/spectrum.txt")));
  int count = 0;
  double xi = 0.0;
  double reference = 0.0;
  while (lines >> xi >> reference) {
    const double value = abs_k(xi);
    const double half_unit =
        xi == 0.0 ? 0.0 : 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(xi))) - 5.0);
    const double abscissa_slack =
        std::max(std::abs(abs_k(xi + half_unit) - value), std::abs(abs_k(xi - half_unit) - value));
    // The slack comes from the K under test; cap it by a bound on |dK/dxi|
    // so a wildly oscillating K cannot loosen its own check.
    EXPECT_LE(abscissa_slack, slope_bound * half_unit) << "xi " << xi;
    EXPECT_NEAR(value, reference, 2e-5 * std::abs(reference) + 2e-5 + abscissa_slack)
        << "xi " << xi;
    ++count;
  }
  EXPECT_EQ(count, 100);
}

}  // namespace
}  // namespace fss
