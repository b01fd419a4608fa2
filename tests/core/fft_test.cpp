// Tests of fss/fft.h: the row FFT (scaling, layout, workspaces) and the
// half-spectrum filter product.

#include "core/fft.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <thread>
#include <vector>

#include "fss/core/error.h"

namespace fss {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;

std::vector<double> random_row(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> value(-100.0, 255.0);
  std::vector<double> row(static_cast<std::size_t>(n));
  for (double& x : row) x = value(rng);
  return row;
}

double max_abs(const std::vector<double>& row) {
  double m = 0.0;
  for (const double x : row) m = std::max(m, std::abs(x));
  return m;
}

// X[k] = sum_j x[j] exp(-2 pi i k j / n), all n bins.
std::vector<Complex> naive_dft(const std::vector<double>& x) {
  const int n = static_cast<int>(x.size());
  std::vector<Complex> spectrum(x.size());
  for (int k = 0; k < n; ++k) {
    Complex sum = 0.0;
    for (int j = 0; j < n; ++j) {
      // Reduce k j mod n first so the angle stays accurate.
      sum += x[j] * std::polar(1.0, -2.0 * kPi * ((static_cast<long>(k) * j) % n) / n);
    }
    spectrum[k] = sum;
  }
  return spectrum;
}

void fill_real(RowFFT::Workspace& workspace, const std::vector<double>& row) {
  std::copy(row.begin(), row.end(), workspace.real().begin());
}

TEST(RowFFT, SizesAndWorkspaceBuffers) {
  for (const int n : {1, 2, 3, 7, 16, 255, 512, 920}) {
    const RowFFT fft(n);
    EXPECT_EQ(fft.size(), n);
    EXPECT_EQ(fft.spectrum_size(), n / 2 + 1);
    RowFFT::Workspace workspace(n);
    EXPECT_EQ(workspace.real().size(), static_cast<std::size_t>(n));
    EXPECT_EQ(workspace.spectrum().size(), static_cast<std::size_t>(n / 2 + 1));
    // The buffers are usable over their whole length (checked by ASan builds too).
    std::fill(workspace.real().begin(), workspace.real().end(), 1.0);
    std::fill(workspace.spectrum().begin(), workspace.spectrum().end(), Complex(2.0, 3.0));
    EXPECT_EQ(workspace.real().back(), 1.0);
    EXPECT_EQ(workspace.spectrum().back(), Complex(2.0, 3.0));
  }
}

TEST(RowFFT, RejectsNonPositiveLength) {
  EXPECT_THROW(RowFFT(0), Error);
  EXPECT_THROW(RowFFT(-4), Error);
}

TEST(RowFFT, InverseOfForwardIsNTimesTheRow) {
  for (const int n : {1, 2, 3, 7, 16, 255, 512, 920}) {
    const RowFFT fft(n);
    RowFFT::Workspace workspace(n);
    const auto row = random_row(n, 17 + n);
    fill_real(workspace, row);
    fft.forward(workspace);
    fft.inverse(workspace);
    // FFT rounding grows like log n; 1e-9 of the row's scale is ample.
    const double tolerance = 1e-9 * n * max_abs(row);
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(workspace.real()[j], n * row[j], tolerance) << "n " << n << " j " << j;
    }
  }
}

TEST(RowFFT, ForwardIsTheUnnormalizedDft) {
  for (const int n : {12, 13, 1, 2}) {
    const RowFFT fft(n);
    RowFFT::Workspace workspace(n);
    const auto row = random_row(n, 5 + n);
    fill_real(workspace, row);
    fft.forward(workspace);
    const auto expected = naive_dft(row);
    // The naive sum itself rounds at ~n ulps of the row's l1 norm.
    const double tolerance = 1e-9 * n * max_abs(row);
    for (int k = 0; k <= n / 2; ++k) {
      EXPECT_NEAR(workspace.spectrum()[k].real(), expected[k].real(), tolerance) << n << " " << k;
      EXPECT_NEAR(workspace.spectrum()[k].imag(), expected[k].imag(), tolerance) << n << " " << k;
    }
  }
}

TEST(RowFFT, ForwardOfAPureToneHitsOneBin) {
  // x[j] = cos(2 pi 3 j / 16): X[3] = 8, every other half-spectrum bin 0.
  const int n = 16;
  const RowFFT fft(n);
  RowFFT::Workspace workspace(n);
  for (int j = 0; j < n; ++j) workspace.real()[j] = std::cos(2.0 * kPi * 3 * j / n);
  fft.forward(workspace);
  for (int k = 0; k <= n / 2; ++k) {
    const Complex expected = k == 3 ? Complex(8.0, 0.0) : Complex(0.0, 0.0);
    EXPECT_NEAR(std::abs(workspace.spectrum()[k] - expected), 0.0, 1e-12) << k;  // rounding
  }
}

TEST(RowFFT, OnePlanManyWorkspacesAndThreads) {
  // The plan is shared; each thread owns its workspace. Results must equal the
  // serial ones bit for bit (same plan, same input).
  const int n = 920;
  const RowFFT fft(n);
  const int rows = 8;
  std::vector<std::vector<double>> expected(rows);
  for (int r = 0; r < rows; ++r) {
    RowFFT::Workspace workspace(n);
    fill_real(workspace, random_row(n, 100 + r));
    fft.forward(workspace);
    for (auto& bin : workspace.spectrum()) bin *= Complex(0.5, -0.25);
    fft.inverse(workspace);
    expected[r].assign(workspace.real().begin(), workspace.real().end());
  }
  std::vector<std::vector<double>> got(rows);
  auto work = [&](int first) {
    RowFFT::Workspace workspace(n);
    for (int r = first; r < rows; r += 2) {
      fill_real(workspace, random_row(n, 100 + r));
      fft.forward(workspace);
      for (auto& bin : workspace.spectrum()) bin *= Complex(0.5, -0.25);
      fft.inverse(workspace);
      got[r].assign(workspace.real().begin(), workspace.real().end());
    }
  };
  std::thread a(work, 0);
  std::thread b(work, 1);
  a.join();
  b.join();
  for (int r = 0; r < rows; ++r) EXPECT_EQ(got[r], expected[r]) << r;
}

// A random filter on the half spectrum, real at DC (where a conjugate
// symmetric filter must be real) and fully complex at every other bin,
// including the Nyquist bin of an even n.
std::vector<Complex> random_filter(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  std::vector<Complex> filter(static_cast<std::size_t>(n / 2 + 1));
  for (auto& h : filter) h = Complex(value(rng), value(rng));
  filter[0] = Complex(filter[0].real(), 0.0);
  return filter;
}

TEST(MultiplyHalfSpectrum, MatchesRealPartOfFullComplexFiltering) {
  for (const int n : {16, 17, 2, 3, 920, 255}) {
    const auto row = random_row(n, 31 + n);
    const auto filter = random_filter(n, 77 + n);
    ASSERT_EQ(filter.size(), static_cast<std::size_t>(n / 2 + 1));

    // Library: r2c, multiply on the half spectrum, c2r, divide by n.
    const RowFFT fft(n);
    RowFFT::Workspace workspace(n);
    fill_real(workspace, row);
    fft.forward(workspace);
    multiply_half_spectrum(workspace.spectrum(), filter, n);
    fft.inverse(workspace);

    // Reference: the full complex filter H on all n bins, H(-f) = conj H(f)
    // except at the Nyquist bin of an even n, where H is used as given (it is
    // not conjugate symmetric there); the real part of the complex IDFT.
    const auto spectrum = naive_dft(row);
    std::vector<Complex> full_filter(static_cast<std::size_t>(n));
    for (int f = 0; f < n; ++f) {
      if (f <= n / 2) {
        full_filter[f] = filter[f];
      } else {
        full_filter[f] = std::conj(filter[n - f]);
      }
    }
    const double scale = max_abs(row) * 2.0 * std::sqrt(2.0);  // |x| |H| bound
    for (int j = 0; j < n; ++j) {
      Complex sum = 0.0;
      for (int f = 0; f < n; ++f) {
        sum += spectrum[f] * full_filter[f] *
               std::polar(1.0, 2.0 * kPi * ((static_cast<long>(f) * j) % n) / n);
      }
      const double expected = sum.real() / n;
      // The naive O(n^2) reference rounds at ~n eps of the scale; 1e-12 n is
      // a few hundred times that and still far below any layout error.
      EXPECT_NEAR(workspace.real()[j] / n, expected, 1e-12 * n * scale) << "n " << n << " j " << j;
    }
  }
}

TEST(MultiplyHalfSpectrum, NyquistBinUsesTheRealPartOfTheFilter) {
  // Direct check of the half-spectrum values for n = 8.
  const int n = 8;
  std::vector<Complex> spectrum = {{1, 0}, {2, 1}, {0, -3}, {4, 4}, {5, 0}};
  const std::vector<Complex> filter = {{2, 0}, {0, 1}, {1, 1}, {-1, 0.5}, {3, 7}};
  auto expected = spectrum;
  for (int i = 0; i < 4; ++i) expected[i] *= filter[i];
  expected[4] = Complex(5.0 * 3.0, 0.0);  // X Re(H); X is real at Nyquist
  multiply_half_spectrum(spectrum, filter, n);
  for (int i = 0; i <= n / 2; ++i) EXPECT_EQ(spectrum[i], expected[i]) << i;

  // Odd n has no Nyquist bin: every bin is a plain product.
  std::vector<Complex> odd = {{1, 0}, {2, 1}, {0, -3}, {4, 4}};
  const std::vector<Complex> odd_filter = {{2, 0}, {0, 1}, {1, 1}, {3, 7}};
  auto odd_expected = odd;
  for (int i = 0; i < 4; ++i) odd_expected[i] *= odd_filter[i];
  multiply_half_spectrum(odd, odd_filter, 7);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(odd[i], odd_expected[i]) << i;
}

}  // namespace
}  // namespace fss
