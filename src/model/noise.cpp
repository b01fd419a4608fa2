#include "fss/model/noise.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/vectorize.h"
#include "fss/core/error.h"

namespace fss {

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += kSplitmix64Gamma);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

namespace {
std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// lambda2 = snr^2 / 100, refused unless it is a finite normal number: 0 or
// infinity would turn every observation into NaN (0 / 0, inf * 0).
double checked_lambda2(double snr) {
  const double lambda2 = snr * snr / 100.0;
  if (!(std::isfinite(lambda2) && lambda2 >= DBL_MIN)) {
    throw_usage_error("snr = " + format_exact(snr) +
                      " is out of range: snr^2 / 100 must be a finite, nonzero double "
                      "(snr between 1.5e-153 and 1.3e155)");
  }
  return lambda2;
}
}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t channel, std::uint64_t frame,
                           std::uint64_t row, std::uint64_t lane) {
  // Hash the coordinates into one key, each step a full splitmix64 round,
  // then expand the key into the 256-bit state.
  std::uint64_t key = seed;
  for (const std::uint64_t coordinate : {channel, frame, row, lane}) {
    std::uint64_t x = key ^ rotl(coordinate + 0x632be59bd9b4e019ULL, 17);
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

double poisson_variate(double lambda, RandomStream& stream) {
  if (!(lambda > 0.0)) return 0.0;
  if (lambda < kKnuthLimit) {
    // Knuth: multiply uniforms until the product is <= exp(-lambda); the
    // variate is the number of multiplications minus one.
    const double limit = std::exp(-lambda);
    double product = stream.uniform();
    double count = 0.0;
    while (product > limit) {
      product *= stream.uniform();
      count += 1.0;
    }
    return count;
  }
  // Normal approximation, rounded; a negative value (probability < 1e-12 at
  // lambda = 50) is clamped to 0.
  return round_nonnegative(lambda + std::sqrt(lambda) * stream.standard_normal());
}

PoissonSNR::PoissonSNR(double snr) : lambda2_(checked_lambda2(snr)) {}

double PoissonSNR::operator()(double e, RandomStream& stream) const {
  // P / lambda2 with P ~ Poisson(max(e, 0) lambda2)
  return poisson_variate(std::max(e, 0.0) * lambda2_, stream) / lambda2_;
}

}  // namespace fss

namespace fss {

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

namespace {

RandomStream lane_stream(const RowNoiseId& id, std::uint64_t frame, NoiseLane lane) {
  return {id.seed, id.channel, frame, id.row, static_cast<std::uint64_t>(lane)};
}

// normals[x] for x < n (the buffer holds n rounded up to even): output x of
// a Box-Muller batch whose pair j takes U1 = stream's (2j)-th draw,
// U2 = its (2j+1)-th.
void draw_normals(RandomStream stream, std::size_t n, std::vector<double>& u1,
                  std::vector<double>& u2, std::vector<double>& normals, bool portable = false) {
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
}  // namespace

double poisson_snr_variance(double e, double lambda2) {
  // Var(P / lambda2) = (lambda [+ 1/12 on the normal branch]) / lambda2^2
  const double signal = std::max(e, 0.0);
  const double rounding = signal * lambda2 >= kKnuthLimit ? 1.0 / (12.0 * lambda2 * lambda2) : 0.0;
  return signal / lambda2 + rounding;
}

PoissonRowSampler::PoissonRowSampler(double snr) : lambda2_(checked_lambda2(snr)) {}

void PoissonRowSampler::draw_charge(std::span<const double> lambda, const RowNoiseId& id,
                                    std::size_t knuth_pixels) {
  const std::size_t n = lambda.size();
  draw_normals(lane_stream(id, id.frame, NoiseLane::kFrameNormal), n, u1_, u2_, normals_);
  if (knuth_pixels == 0) return;
  RandomStream knuth_stream = lane_stream(id, id.frame, NoiseLane::kFrameKnuth);
  for (std::size_t x = 0; x < n; ++x) {
    if (lambda[x] < kKnuthLimit) normals_[x] = poisson_variate(lambda[x], knuth_stream);
  }
}

std::size_t PoissonRowSampler::intensities_of(std::span<const double> e, double dark,
                                              std::vector<double>& lambda_row,
                                              std::vector<double>& root_row) const {
  const std::size_t n = e.size();
  lambda_row.resize(n);
  root_row.resize(n);
  std::size_t knuth_pixels = 0;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    // Locals, not the captured references, so that the loop vectorizes.
    const double* __restrict intensity = e.data();
    double* __restrict lambda = lambda_row.data();
    double* __restrict root = root_row.data();
    const double lambda2 = lambda2_;
    const double dark_electrons = dark;
    std::size_t count = 0;
    for (std::size_t x = 0; x < n; ++x) {
      lambda[x] = std::max(intensity[x], 0.0) * lambda2 + dark_electrons;
      root[x] = std::sqrt(lambda[x]);
      count += lambda[x] < kKnuthLimit ? 1 : 0;
    }
    knuth_pixels = count;
  });
  return knuth_pixels;
}

void PoissonRowSampler::accumulate(std::span<const double> e, const RowNoiseId& id, double gain,
                                   std::span<double> out) {
  const std::size_t knuth_pixels = intensities_of(e, 0.0, lambda_, root_);
  accumulate(Intensities{lambda_, root_, knuth_pixels}, id, gain, out);
}

void PoissonRowSampler::accumulate(const Intensities& row, const RowNoiseId& id, double gain,
                                   std::span<double> out) {
  const std::size_t n = row.lambda.size();
  // One normal per pixel, normal x for pixel x; Knuth's branch where
  // lambda < 50 takes the place of the pixel's unused normal.
  draw_charge(row.lambda, id, row.knuth_pixels);
  // Normal branch elsewhere: P = round(lambda + sqrt(lambda) N);
  // out += gain P / lambda2.
  const double scale = gain / lambda2_;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict lambda = row.lambda.data();
    const double* __restrict root = row.root.data();
    const double* __restrict normal = normals_.data();
    double* __restrict sum = out.data();
    const double factor = scale;
    for (std::size_t x = 0; x < n; ++x) {
      const double rounded = round_nonnegative(lambda[x] + root[x] * normal[x]);
      sum[x] += factor * (lambda[x] < kKnuthLimit ? normal[x] : rounded);
    }
  });
}

void PoissonRowSampler::accumulate_readout(std::span<const double> e, const RowNoiseId& id,
                                           double gain, const SensorReadout& readout,
                                           std::span<double> out) {
  const std::size_t n = e.size();
  // The charge P, drawn as accumulate() draws it: normals from lane 0, and
  // Knuth's variates from lane 1 in place of the unused normals.
  // (Two statements: the span of lambda_ must be taken after it is resized.)
  const std::size_t knuth_pixels = intensities_of(e, readout.dark_electrons, lambda_, root_);
  draw_charge(lambda_, id, knuth_pixels);
  // The read noise's normals from lane 4 (zeros without read noise).
  if (readout.read_noise_electrons != 0.0) {
    draw_normals(lane_stream(id, id.frame, NoiseLane::kReadNoise), n, u1_, u2_, read_normals_,
                 /*portable=*/true);
  } else {
    read_normals_.assign(n, 0.0);
  }
  // out += gain * read(P, R) / lambda2 (SensorReadout::read, inline so that
  // the loop vectorizes)
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict lambda = lambda_.data();
    const double* __restrict root = root_.data();
    const double* __restrict normal = normals_.data();
    const double* __restrict read = read_normals_.data();
    double* __restrict sum = out.data();
    const double scale = gain / lambda2_;
    const double well = readout.full_well_electrons;
    const double sigma = readout.read_noise_electrons;
    const double dark = readout.dark_electrons;
    const bool adc = readout.adc();
    const double adc_gain = adc ? readout.adc_gain_electrons_per_count : 1.0;
    const double adc_max = readout.adc_max_counts;
    for (std::size_t x = 0; x < n; ++x) {
      const double rounded = round_nonnegative(lambda[x] + root[x] * normal[x]);
      const double charge = lambda[x] < kKnuthLimit ? normal[x] : rounded;
      const double q = std::min(charge, well) + sigma * read[x];
      const double counted = std::min(round_nonnegative(q / adc_gain), adc_max) * adc_gain;
      sum[x] += scale * ((adc ? counted : q) - dark);
    }
  });
}

void PoissonRowSampler::add_read_noise(const RowNoiseId& id, double scale, std::span<double> out) {
  draw_normals(lane_stream(id, id.frame, NoiseLane::kReadNoise), out.size(), u1_, u2_,
               read_normals_, /*portable=*/true);
  for (std::size_t x = 0; x < out.size(); ++x) out[x] += scale * read_normals_[x];
}

AggregatedRowSampler::AggregatedRowSampler(double snr) : lambda2_(checked_lambda2(snr)) {}

std::size_t AggregatedRowSampler::intensities_of(std::span<const double> e, double dark,
                                                 IntensityRows& rows) const {
  const std::size_t n = e.size();
  rows.lambda.resize(n);
  rows.mean_part.resize(n);
  rows.variance_part.resize(n);
  std::size_t normal_pixels = 0;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    // Locals, not the captured references, so that the loop vectorizes.
    const double* __restrict intensity = e.data();
    double* __restrict lambda = rows.lambda.data();
    double* __restrict mean = rows.mean_part.data();
    double* __restrict variance = rows.variance_part.data();
    const double lambda2 = lambda2_;
    const double dark_electrons = dark;
    std::size_t count = 0;
    for (std::size_t x = 0; x < n; ++x) {
      lambda[x] = std::max(intensity[x], 0.0) * lambda2 + dark_electrons;
      const bool normal = lambda[x] >= kKnuthLimit;
      mean[x] = normal ? lambda[x] : 0.0;
      variance[x] = normal ? lambda[x] + 1.0 / 12.0 : 0.0;
      count += normal ? 1 : 0;
    }
    normal_pixels = count;
  });
  return normal_pixels;
}

void AggregatedRowSampler::add_frame(std::span<const double> e, const RowNoiseId& id, double gain,
                                     std::span<double> out, const SensorReadout* readout) {
  const double dark = readout != nullptr ? readout->dark_electrons : 0.0;
  const std::size_t normal_pixels = intensities_of(e, dark, intensities_);
  add_frame(FrameIntensities{intensities_.lambda, intensities_.mean_part,
                             intensities_.variance_part, normal_pixels},
            id, gain, out, readout);
}

void AggregatedRowSampler::add_frame(const FrameIntensities& frame, const RowNoiseId& id,
                                     double gain, std::span<double> out,
                                     const SensorReadout* readout) {
  const std::size_t n = frame.lambda.size();
  if (!has_frame_) {  // the row's first frame
    mean_.assign(n, 0.0);
    variance_.assign(n, 0.0);
    has_frame_ = true;
  }
  // Normal branch: M += alpha lambda, V += alpha^2 (lambda + 1/12); the
  // parts are 0 on Knuth's branch, and alpha 0 or alpha^2 0 adds a zero that
  // leaves every sum's bits as they are.
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict mean_part = frame.mean_part.data();
    const double* __restrict variance_part = frame.variance_part.data();
    double* __restrict mean = mean_.data();
    double* __restrict variance = variance_.data();
    const double alpha = gain;
    const double alpha_squared = gain * gain;
    for (std::size_t x = 0; x < n; ++x) {
      mean[x] += alpha * mean_part[x];
      variance[x] += alpha_squared * variance_part[x];
    }
  });
  if (frame.normal_pixels > 0) has_normal_ = true;
  if (readout != nullptr) add_readout_terms(gain, *readout);
  if (frame.normal_pixels == n) return;
  add_knuth_branch(frame.lambda, n - frame.normal_pixels, id, gain, out);
}

void AggregatedRowSampler::add_knuth_branch(std::span<const double> lambda,
                                            std::size_t knuth_pixels, const RowNoiseId& id,
                                            double gain, std::span<double> out) {
  // Drawn now: out += gain P / lambda2, uniforms in pixel order.
  RandomStream knuth_stream = lane_stream(id, id.frame, NoiseLane::kAggregateKnuth);
  const double scale = gain / lambda2_;
  AggregatedRowPlan::KnuthFrame* recorded = nullptr;
  if (plan_ != nullptr && plan_->knuth_pixels + knuth_pixels <= max_knuth_pixels_) {
    plan_->knuth_pixels += knuth_pixels;
    recorded = &plan_->knuth.emplace_back();
    recorded->frame = id.frame;
    recorded->gain = gain;
    recorded->pixels.reserve(knuth_pixels);
    recorded->lambdas.reserve(knuth_pixels);
  } else if (plan_ != nullptr) {
    plan_->knuth_pixels = max_knuth_pixels_ + 1;  // too many: the row is not recorded
  }
  for (std::size_t x = 0; x < lambda.size(); ++x) {
    if (lambda[x] < kKnuthLimit) {
      out[x] += scale * poisson_variate(lambda[x], knuth_stream);
      if (recorded != nullptr) {
        recorded->pixels.push_back(static_cast<std::uint32_t>(x));
        recorded->lambdas.push_back(lambda[x]);
      }
    }
  }
}

void AggregatedRowSampler::add_readout_terms(double gain, const SensorReadout& readout) {
  // Every pixel: M -= alpha dark (dark-frame correction), V += alpha^2 sigma_r^2.
  const double read_variance = readout.read_noise_electrons * readout.read_noise_electrons;
  for (std::size_t x = 0; x < mean_.size(); ++x) {
    mean_[x] -= gain * readout.dark_electrons;
    variance_[x] += gain * gain * read_variance;
  }
  has_normal_ = true;
}

void AggregatedRowSampler::add_normals(std::span<const double> mean_photons,
                                       std::span<const double> variance_photons,
                                       const RowNoiseId& id, std::span<double> out) {
  const std::size_t n = mean_photons.size();
  draw_normals(lane_stream(id, 0, NoiseLane::kAggregateNormal), n, u1_, u2_, normals_,
               /*portable=*/true);
  // out += (M + sqrt(V) N) / lambda2
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict mean = mean_photons.data();
    const double* __restrict variance = variance_photons.data();
    const double* __restrict normal = normals_.data();
    double* __restrict sum = out.data();
    const double lambda2 = lambda2_;
    for (std::size_t x = 0; x < n; ++x) {
      sum[x] += (mean[x] + std::sqrt(variance[x]) * normal[x]) / lambda2;
    }
  });
}

void AggregatedRowSampler::finish(const RowNoiseId& id, std::span<double> out) {
  if (has_normal_) add_normals(mean_, variance_, id, out);
  if (plan_ != nullptr) {
    if (plan_->knuth_pixels <= max_knuth_pixels_) {
      if (has_normal_) {
        plan_->mean = mean_;
        plan_->variance = variance_;
      }
      plan_->recorded = true;
    } else {
      *plan_ = AggregatedRowPlan();
    }
    plan_ = nullptr;
  }
  has_frame_ = false;
  has_normal_ = false;
}

void AggregatedRowSampler::record_next_row(AggregatedRowPlan* plan, std::size_t max_knuth_pixels) {
  *plan = AggregatedRowPlan();
  plan_ = plan;
  max_knuth_pixels_ = max_knuth_pixels;
}

void AggregatedRowSampler::replay(const AggregatedRowPlan& plan, const RowNoiseId& id,
                                  std::span<double> out) {
  // The Knuth-branch frames in their order, each from its own lane and in
  // pixel order, then the normal: add_frame()'s and finish()'s operations.
  for (const AggregatedRowPlan::KnuthFrame& frame : plan.knuth) {
    RandomStream knuth_stream = lane_stream(id, frame.frame, NoiseLane::kAggregateKnuth);
    const double scale = frame.gain / lambda2_;
    for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
      out[frame.pixels[i]] += scale * poisson_variate(frame.lambdas[i], knuth_stream);
    }
  }
  if (!plan.mean.empty()) add_normals(plan.mean, plan.variance, id, out);
}

}  // namespace fss
