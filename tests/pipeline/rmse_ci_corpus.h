// A corpus of generated inputs for rmse_contrast_invariant, and a plain
// reference of it that fixes every summation order exactly as the library
// does (docs/method.md §5), so that the two agree bit for bit.
//
// The corpus covers the ground truths fssim meets (8-bit levels, 16-bit
// levels k / 257, integers up to 65535, float TIFF values) and awkward ones
// (negatives, -0 and +0, a single group, +-1e150, denormals, integers just
// past 65535), restorations with and without ties (noise, quarter steps,
// integers, a constant, values one ulp apart, one huge outlier, +-1e300
// (whose squares overflow), a range that overflows, denormals only), window
// sizes from one pixel to above 2^22 pixels, one and three channels. Only
// +, -, *, / and rounding make the values: the same bits on every platform.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/image.h"
#include "support/test_util.h"

namespace fss::test {

// The order-preserving bits of a value (-0 and +0 are one value) and back.
inline std::uint64_t ordered_value_bits(double value) {
  if (value == 0.0) value = 0.0;
  const auto bits = std::bit_cast<std::uint64_t>(value);
  return (bits >> 63) ? ~bits : bits | (std::uint64_t{1} << 63);
}
inline double value_of_ordered_bits(std::uint64_t bits) {
  return std::bit_cast<double>((bits >> 63) ? bits ^ (std::uint64_t{1} << 63) : ~bits);
}

// Mean and sum of squared deviations of mid over [begin, end), each summed
// in rank order.
inline std::pair<double, double> reference_moments(const std::vector<double>& mid,
                                                   std::size_t begin, std::size_t end) {
  double sum = 0.0;
  for (std::size_t i = begin; i < end; ++i) sum += mid[i];
  const double mean = sum / static_cast<double>(end - begin);
  double m2 = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    const double d = mid[i] - mean;
    m2 += d * d;
  }
  return {mean, m2};
}

// One channel's sum of E[(a'_p - b'_p)^2]: m2 of a's groups in rank order,
// then m2 of b's groups of more than one pixel in rank order, plus the sum
// of (B_G - B_H)^2 over b's ranks, b's ties ranked by a's group.
inline double reference_channel_sum(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t n = a.size();
  std::vector<std::uint64_t> a_sorted(n);
  for (std::size_t p = 0; p < n; ++p) a_sorted[p] = ordered_value_bits(a[p]);
  std::sort(a_sorted.begin(), a_sorted.end());
  std::vector<std::uint64_t> levels = a_sorted;
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  auto group_of = [&](std::uint64_t bits) {
    return static_cast<std::size_t>(std::lower_bound(levels.begin(), levels.end(), bits) -
                                    levels.begin());
  };
  std::vector<std::pair<std::uint64_t, std::size_t>> b_sorted(n);
  for (std::size_t p = 0; p < n; ++p) {
    b_sorted[p] = {ordered_value_bits(b[p]), group_of(ordered_value_bits(a[p]))};
  }
  std::sort(b_sorted.begin(), b_sorted.end());
  std::vector<double> mid(n);
  for (std::size_t i = 0; i < n; ++i) {
    mid[i] = 0.5 * (value_of_ordered_bits(a_sorted[i]) + value_of_ordered_bits(b_sorted[i].first));
  }
  double m2_sum = 0.0;
  std::vector<double> a_mean(levels.size());
  for (std::size_t begin = 0, end = 0; begin < n; begin = end) {
    while (end < n && a_sorted[end] == a_sorted[begin]) ++end;
    const auto [mean, m2] = reference_moments(mid, begin, end);
    a_mean[group_of(a_sorted[begin])] = mean;
    m2_sum += m2;
  }
  std::vector<double> b_mean = mid;
  for (std::size_t begin = 0, end = 0; begin < n; begin = end) {
    while (end < n && b_sorted[end].first == b_sorted[begin].first) ++end;
    if (end - begin == 1) continue;
    const auto [mean, m2] = reference_moments(mid, begin, end);
    std::fill(b_mean.begin() + static_cast<std::ptrdiff_t>(begin),
              b_mean.begin() + static_cast<std::ptrdiff_t>(end), mean);
    m2_sum += m2;
  }
  double cross = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = a_mean[b_sorted[i].second] - b_mean[i];
    cross += d * d;
  }
  return m2_sum + cross;
}

// rmse_contrast_invariant(a, a_offset, b, first, end) the plain way.
inline double reference_rmse_contrast_invariant(const Image& a, int a_offset, const Image& b,
                                                int first, int end) {
  double sum = 0.0;
  for (int c = 0; c < b.channels; ++c) {
    std::vector<double> av;
    std::vector<double> bv;
    for (int y = 0; y < b.height; ++y) {
      for (int x = first; x < end; ++x) {
        av.push_back(a.at(c, y, x + a_offset));
        bv.push_back(b.at(c, y, x));
      }
    }
    sum += reference_channel_sum(av, bv);
  }
  const double count = static_cast<double>(end - first) * b.height * b.channels;
  return std::sqrt(sum / count);
}

// splitmix64: a portable stream of 64-bit values.
class CorpusRandom {
 public:
  explicit CorpusRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }  // [0, 1)
  // About a standard normal: the sum of four uniforms, centred and scaled.
  double normal() { return (unit() + unit() + unit() + unit() - 2.0) * 1.7320508075688772; }

 private:
  std::uint64_t state_;
};

struct CorpusCase {
  std::string name;
  Image a;  // wider than b: b's column x faces a's column x + a_offset
  int a_offset = 0;
  Image b;
  int first = 0;  // b's window [first, end)
  int end = 0;
};

// A smooth gray level in [0, 255] with texture, made of triangle waves.
inline double corpus_base(int x, int y, int c, CorpusRandom& random) {
  auto triangle = [](double t) { return std::abs(t - std::floor(t) - 0.5) * 4.0 - 1.0; };
  const double v = 127.5 + 95.0 * triangle(0.013 * x + 0.3 * c) * triangle(0.021 * y + 0.1) +
                   30.0 * (random.unit() - 0.5);
  return std::clamp(v, 0.0, 255.0);
}

inline const std::vector<std::string>& corpus_a_kinds() {
  static const std::vector<std::string> kinds = {"a8",   "a16",    "a16int", "afloat",   "aneg",
                                                 "afew", "aconst", "azeros", "aextreme", "a65536"};
  return kinds;
}
inline const std::vector<std::string>& corpus_b_kinds() {
  static const std::vector<std::string> kinds = {"bnoise",   "bquarter", "bint",   "bconst",
                                                 "bulps",    "boutlier", "brange", "bdenorm",
                                                 "bextreme", "bneg",     "bequal", "bhuge"};
  return kinds;
}

// A ground-truth value of `kind` at a pixel whose smooth level is `base`.
inline double corpus_a_value(const std::string& kind, double base, CorpusRandom& random) {
  if (kind == "a8") return std::round(base);
  if (kind == "a16") return std::round(base * 257.0) / 257.0;
  if (kind == "a16int") return std::round(base * 257.0);
  if (kind == "afloat") return static_cast<double>(static_cast<float>(base));
  if (kind == "aneg") return std::round(base * 1.3 - 40.0);
  if (kind == "afew") return base < 90.0 ? 0.5 : (base < 160.0 ? 1.5 : 2.5);
  if (kind == "aconst") return 7.25;
  if (kind == "azeros") {
    const double values[] = {-0.0, 0.0, 1.0, 2.0};
    return values[random.next() % 4];
  }
  if (kind == "aextreme") {
    const double values[] = {-1e150, 1e150, 4.9e-324, -4.9e-324,    2.2250738585072014e-308,
                             0.0,    -0.0,  1.0,      1.0 + 0x1p-52};
    const std::uint64_t pick = random.next() % 12;
    return pick < 9 ? values[pick] : std::round(base);
  }
  return std::round(base * 257.0) + 1.0;  // a65536: 1 .. 65536
}

// A restored value of `kind` facing ground-truth level `base`.
inline double corpus_b_value(const std::string& kind, double base, CorpusRandom& random) {
  const double noisy = base + 3.0 * random.normal();
  if (kind == "bnoise") return noisy;
  if (kind == "bquarter") return std::round(4.0 * noisy) / 4.0;
  if (kind == "bint") return std::round(noisy);
  if (kind == "bconst") return -3.5;
  if (kind == "bulps") return 1.0 + static_cast<double>(random.next() % 4) * 0x1p-52;
  if (kind == "boutlier") return random.next() % 997 == 0 ? 1e150 : noisy;
  if (kind == "bhuge") {
    const std::uint64_t pick = random.next() % 5;
    return pick == 0 ? 1e300 : (pick == 1 ? -1e300 : noisy);
  }
  if (kind == "brange") {
    const std::uint64_t pick = random.next() % 50;
    return pick == 0 ? -1.7e308 : (pick == 1 ? 1.7e308 : noisy);
  }
  if (kind == "bdenorm") {
    const std::uint64_t pick = random.next() % 8;
    if (pick == 0) return 0.0;
    if (pick == 1) return -0.0;
    return static_cast<double>(random.next() % 1000) * 4.9e-324;
  }
  if (kind == "bextreme") {
    const double values[] = {1e150,     -1e150, 1e-300, -1e-300, 4.9e-324,
                             -4.9e-324, 0.0,    -0.0,   1.0,     1.0 + 0x1p-52};
    const std::uint64_t pick = random.next() % 14;
    return pick < 10 ? values[pick] : noisy;
  }
  if (kind == "bneg") return (noisy - 128.0) * 1e5;
  return random.next() % 2 == 0 ? 17.0 : noisy;  // bequal: half the pixels one value
}

// A case of w x h x channels: b has a column more on each side of the window
// and a a further two, so the window and the offset are exercised.
inline CorpusCase make_corpus_case(const std::string& a_kind, const std::string& b_kind, int w,
                                   int h, int channels) {
  CorpusCase k;
  k.name = a_kind + "-" + b_kind + "-" + std::to_string(w) + "x" + std::to_string(h) + "x" +
           std::to_string(channels);
  std::uint64_t seed = 0;
  for (const char ch : k.name) seed = seed * 131 + static_cast<unsigned char>(ch);
  CorpusRandom random(seed);
  k.b = Image(w + 2, h, channels);
  k.a = Image(w + 6, h, channels);
  k.a_offset = 2;
  k.first = 1;
  k.end = w + 1;
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < k.a.width; ++x) {
        const double base = corpus_base(x, y, c, random);
        k.a.at(c, y, x) = corpus_a_value(a_kind, base, random);
        const int bx = x - k.a_offset;
        if (bx >= 0 && bx < k.b.width) k.b.at(c, y, bx) = corpus_b_value(b_kind, base, random);
      }
    }
  }
  return k;
}

// Under AddressSanitizer, which makes the largest cases minutes long, the corpus is the cases of
// at most this many samples (width x height x channels): every kind of ground truth and
// restoration and every shape but the largest; the Release suite runs them all.
inline std::size_t corpus_sample_limit() {
  return kAddressSanitizer ? std::size_t{200000} : std::numeric_limits<std::size_t>::max();
}

// Calls f(case) for each case of the corpus of at most corpus_sample_limit() samples, one at a
// time (the largest holds 4.4 M pixels); returns how many cases it left out.
inline std::size_t for_each_corpus_case(const std::function<void(const CorpusCase&)>& f) {
  std::size_t skipped = 0;
  const auto visit = [&](const std::string& a, const std::string& b, int w, int h, int c) {
    if (static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c) >
        corpus_sample_limit()) {
      ++skipped;
      return;
    }
    f(make_corpus_case(a, b, w, h, c));
  };
  const std::vector<std::string>& as = corpus_a_kinds();
  const std::vector<std::string>& bs = corpus_b_kinds();
  for (const auto& [w, h] : {std::pair{1, 1}, {1, 7}, {9, 1}, {3, 2}, {17, 13}, {64, 64}}) {
    for (const std::string& a : as) {
      for (const std::string& b : bs) visit(a, b, w, h, 1);
    }
  }
  for (const std::string& a : as) visit(a, "bnoise", 37, 11, 3);
  const std::vector<std::pair<std::string, std::string>> camera = {
      {"a8", "bnoise"},   {"a8", "bquarter"}, {"a8", "bint"},          {"a8", "boutlier"},
      {"a8", "bequal"},   {"a16", "bnoise"},  {"afloat", "bnoise"},    {"aneg", "bnoise"},
      {"a16int", "bint"}, {"afew", "bnoise"}, {"aextreme", "bextreme"}};
  for (const auto& [a, b] : camera) visit(a, b, 252, 512, 1);
  visit("a8", "bnoise", 252, 512, 3);
  const std::vector<std::pair<std::string, std::string>> medium = {
      {"a8", "bnoise"},   {"a8", "bquarter"}, {"a16", "bnoise"}, {"afloat", "bnoise"},
      {"a8", "boutlier"}, {"a8", "brange"},   {"a8", "bconst"},  {"aconst", "bnoise"},
      {"a8", "bint"},     {"a8", "bdenorm"},  {"aneg", "bneg"},  {"a8", "bulps"}};
  for (const auto& [a, b] : medium) visit(a, b, 400, 350, 1);
  visit("a8", "bnoise", 700, 500, 3);
  visit("afloat", "bquarter", 700, 500, 1);
  visit("a16int", "bnoise", 700, 500, 1);
  for (const auto& [a, b] : std::vector<std::pair<std::string, std::string>>{
           {"a8", "bnoise"}, {"a16", "bnoise"}, {"afloat", "bnoise"}, {"a8", "bextreme"}}) {
    visit(a, b, 1200, 1000, 1);
  }
  visit("a8", "bnoise", 2100, 2100, 1);
  visit("a8", "bint", 2100, 2100, 1);
  return skipped;
}

}  // namespace fss::test
