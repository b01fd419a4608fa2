// The random streams of the photon noise and their Box-Muller normals
// (noise_stream.h). Compiled with the samplers' flags (CMakeLists.txt): the
// portable Box-Muller's loop must vectorize and round every operation.
#include "model/noise_stream.h"

#include <array>
#include <bit>
#include <cmath>

#include "core/vectorize.h"

namespace fss {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += kSplitmix64Gamma);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame,
                           std::uint64_t row, std::uint64_t lane) {
  // Hash the coordinates into one key, each step a full splitmix64 round,
  // then expand the key into the 256-bit state.
  std::uint64_t key = seed;
  for (const std::uint64_t coordinate : {channel, frame, row, lane}) {
    std::uint64_t x = key ^ detail::rotate_left(coordinate + 0x632be59bd9b4e019ULL, 17);
    key = splitmix64(x);
  }
  for (auto& word : state_) word = splitmix64(key);
}

double RandomStream::standard_normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_normal_;
  }
  // N = sqrt(-2 ln U1) cos(2 pi U2), twin sqrt(-2 ln U1) sin(2 pi U2); U1 in (0, 1].
  const double radius = std::sqrt(-2.0 * std::log(uniform_open_zero()));
  const double angle = 2.0 * M_PI * uniform();
  spare_normal_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

namespace {

// ln u for a normal double u > 0, with +, -, *, / and exact bit operations
// only: u = 2^E m with m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s) =
// 2 (s + s^3 / 3 + s^5 / 5 + ...) with s = (m - 1) / (m + 1), |s| < 0.1716,
// summed to s^23 (the next term is below 1e-18 relative); E ln 2 in two
// parts, the first exact for |E| < 2^21 (fdlibm's split of ln 2).
[[gnu::always_inline]] inline double portable_log(double u) {
  constexpr double kLn2High = 0x1.62e42feep-1;
  constexpr double kLn2Low = 0x1.a39ef35793c76p-33;
  constexpr double kSqrt2 = 0x1.6a09e667f3bcdp+0;
  const auto bits = std::bit_cast<std::uint64_t>(u);
  // The biased exponent field, read as a double by the 2^52 trick: exact.
  const double biased = std::bit_cast<double>(0x4330000000000000ULL | (bits >> 52)) - 0x1p52;
  const double mantissa =
      std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);
  const bool high = mantissa > kSqrt2;
  const double m = high ? 0.5 * mantissa : mantissa;
  const double exponent = (high ? biased + 1.0 : biased) - 1023.0;
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  // 1 / 23, 1 / 21, ..., 1 / 3: constants, correctly rounded by the compiler.
  constexpr std::array<double, 11> kInverseOdd = [] {
    std::array<double, 11> c{};
    for (int i = 0; i < 11; ++i) c[i] = 1.0 / (23 - 2 * i);
    return c;
  }();
  double series = kInverseOdd[0];
  for (int i = 1; i < 11; ++i) series = series * s2 + kInverseOdd[i];
  const double ln_m = 2.0 * s + 2.0 * s * (s2 * series);
  return exponent * kLn2High + (exponent * kLn2Low + ln_m);
}

// cos(2 pi u) and sin(2 pi u) for u in [0, 1], with +, -, * and exact
// operations only: 4u = q + r with q = nearest integer, r in [-1/2, 1/2]
// (both exact), theta = r pi / 2 in [-pi/4, pi/4], Taylor series of sin and
// cos of theta to theta^17 and theta^18 (the next terms are below 1e-19),
// then the quadrant q turns (cos theta, sin theta) by q quarter turns.
[[gnu::always_inline]] inline void portable_cos_sin(double u, double& cosine, double& sine) {
  constexpr double kHalfPi = 0x1.921fb54442d18p+0;
  const double w = 4.0 * u;
  const double q = (w + 0x1p52) - 0x1p52;  // 0, 1, 2, 3 or 4 (4 is a full turn)
  const double theta = (w - q) * kHalfPi;
  const double t2 = theta * theta;
  // sin = theta (1 - t2 / 3! (1 - t2 / (4 5) (1 - ...))), likewise cos.
  // 1 / (n (n - 1)) for n = 18, 17, ..., 2: constants, correctly rounded by the compiler.
  constexpr std::array<double, 17> kInverse = [] {
    std::array<double, 17> c{};
    for (int i = 0; i < 17; ++i) c[i] = 1.0 / ((18 - i) * (17 - i));
    return c;
  }();
  double sin_series = 1.0;  // n = 17, 15, ..., 3: kInverse[1], [3], ..., [15]
  for (int i = 1; i < 17; i += 2) sin_series = 1.0 - t2 * kInverse[i] * sin_series;
  double cos_series = 1.0;  // n = 18, 16, ..., 2: kInverse[0], [2], ..., [16]
  for (int i = 0; i < 17; i += 2) cos_series = 1.0 - t2 * kInverse[i] * cos_series;
  const double s = theta * sin_series;
  const double c = cos_series;
  const bool odd = q == 1.0 || q == 3.0;
  const double a = odd ? s : c;
  const double b = odd ? c : s;
  cosine = (q == 1.0 || q == 2.0) ? -a : a;
  sine = (q == 2.0 || q == 3.0) ? -b : b;
}

}  // namespace

void box_muller_portable(const double* u1, const double* u2, double* z, std::size_t pairs) {
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict first = u1;
    const double* __restrict second = u2;
    double* __restrict normal = z;
    for (std::size_t j = 0; j < pairs; ++j) {
      // sqrt(-2 ln U1) (cos 2 pi U2, sin 2 pi U2)
      const double radius = std::sqrt(-2.0 * portable_log(first[j]));
      double cosine = 0.0;
      double sine = 0.0;
      portable_cos_sin(second[j], cosine, sine);
      normal[2 * j] = radius * cosine;
      normal[2 * j + 1] = radius * sine;
    }
  });
}

void draw_normals(RandomStream stream, std::size_t n, std::vector<double>& u1,
                  std::vector<double>& u2, std::vector<double>& normals, bool portable) {
  const std::size_t pairs = (n + 1) / 2;
  u1.resize(pairs);
  u2.resize(pairs);
  normals.resize(2 * pairs);
  for (std::size_t j = 0; j < pairs; ++j) {
    u1[j] = stream.uniform_open_zero();
    u2[j] = stream.uniform();
  }
  if (portable) {
    box_muller_portable(u1.data(), u2.data(), normals.data(), pairs);
  } else {
    box_muller_batch(u1.data(), u2.data(), normals.data(), pairs);
  }
}

}  // namespace fss
