#include "io/png_samples.h"

#include <cstddef>

// Compiled with -fno-trapping-math (CMakeLists.txt): the selects of doubles
// below then become vector blends, and every loop vectorizes. The samples
// do not depend on it, nor on the instructions the loops are compiled to:
// each operation is exact or correctly rounded the same way in scalar and
// vector code (no contraction into fused multiply-adds: AVX2 alone does not
// enable FMA).
// Channels are converted apart, then interleaved, so that the conversion
// vectorizes (CONTRIBUTING.md, "Hand-written fast paths").

namespace fss::detail {
namespace {

// A value as a sample, the rule of png8_sample (top 255) and of
// png16_sample (top 65535, on value x 257): NaN and values below 0.5 become
// 0, values above the top become the top, then floor(v + 0.5) is v rounded
// half away from zero. It is exact for 0.5 <= v < 2^52: v + 0.5 is a
// multiple of ulp(v), so it could round up to an integer n only by leaving
// the binade [2^e, 2^(e+1)) of v; then n >= 2^(e+1) + 1, more than
// v + 0.5 + ulp(v) can round to. (Below 0.5, 0.49999999999999994 + 0.5
// rounds to 1: those values are set to 0 first.)
[[gnu::always_inline]] inline int stored_sample(double v, double top) {
  v = v >= 0.5 ? v : 0.0;
  v = v < top ? v : top;
  return static_cast<int>(v + 0.5);  // NOLINT(bugprone-incorrect-roundings): exact, see above
}

[[gnu::always_inline]] inline void convert8(const double* __restrict values, int width,
                                            std::uint8_t* __restrict out) {
  for (int x = 0; x < width; ++x)
    out[x] = static_cast<std::uint8_t>(stored_sample(values[x], 255.0));
}

[[gnu::always_inline]] inline void convert16(const double* __restrict values, int width,
                                             std::uint16_t* __restrict out) {
  for (int x = 0; x < width; ++x) {
    out[x] = static_cast<std::uint16_t>(stored_sample(values[x] * 257.0, 65535.0));
  }
}

[[gnu::always_inline]] inline void interleave8(const std::uint8_t* __restrict red,
                                               const std::uint8_t* __restrict green,
                                               const std::uint8_t* __restrict blue, int width,
                                               std::uint8_t* __restrict out) {
  for (int x = 0; x < width; ++x) {
    out[3 * static_cast<std::size_t>(x)] = red[x];
    out[3 * static_cast<std::size_t>(x) + 1] = green[x];
    out[3 * static_cast<std::size_t>(x) + 2] = blue[x];
  }
}

// 16-bit samples big-endian, `channel_count` interleaved.
[[gnu::always_inline]] inline void interleave16(const std::uint16_t* __restrict samples,
                                                int channel_count, int width,
                                                std::uint8_t* __restrict out) {
  const auto n = static_cast<std::size_t>(width);
  if (channel_count == 1) {
    for (std::size_t x = 0; x < n; ++x) {
      out[2 * x] = static_cast<std::uint8_t>(samples[x] >> 8);
      out[2 * x + 1] = static_cast<std::uint8_t>(samples[x]);
    }
    return;
  }
  for (std::size_t x = 0; x < n; ++x) {
    for (std::size_t c = 0; c < 3; ++c) {
      out[6 * x + 2 * c] = static_cast<std::uint8_t>(samples[c * n + x] >> 8);
      out[6 * x + 2 * c + 1] = static_cast<std::uint8_t>(samples[c * n + x]);
    }
  }
}

[[gnu::always_inline]] inline void store_row(const double* const* channels, int channel_count,
                                             int width, int bit_depth, std::uint16_t* scratch,
                                             std::uint8_t* out) {
  const auto n = static_cast<std::size_t>(width);
  if (bit_depth == 8 && channel_count == 1) {
    convert8(channels[0], width, out);
  } else if (bit_depth == 8) {
    auto* bytes = reinterpret_cast<std::uint8_t*>(scratch);
    for (int c = 0; c < 3; ++c) convert8(channels[c], width, bytes + c * n);
    interleave8(bytes, bytes + n, bytes + 2 * n, width, out);
  } else {
    for (int c = 0; c < channel_count; ++c) convert16(channels[c], width, scratch + c * n);
    interleave16(scratch, channel_count, width, out);
  }
}

#if defined(__x86_64__)
[[gnu::target("avx2")]] void store_sample_row_avx2(const double* const* channels, int channel_count,
                                                   int width, int bit_depth, std::uint16_t* scratch,
                                                   std::uint8_t* out) {
  store_row(channels, channel_count, width, bit_depth, scratch, out);
}
#endif

}  // namespace

void store_sample_row_portable(const double* const* channels, int channel_count, int width,
                               int bit_depth, std::uint16_t* scratch, std::uint8_t* out) {
  store_row(channels, channel_count, width, bit_depth, scratch, out);
}

bool sample_rows_use_avx2() {
#if defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  return avx2;
#else
  return false;
#endif
}

void store_sample_row(const double* const* channels, int channel_count, int width, int bit_depth,
                      std::uint16_t* scratch, std::uint8_t* out) {
#if defined(__x86_64__)
  if (sample_rows_use_avx2()) {
    store_sample_row_avx2(channels, channel_count, width, bit_depth, scratch, out);
    return;
  }
#endif
  store_row(channels, channel_count, width, bit_depth, scratch, out);
}

}  // namespace fss::detail
