// Private to src/io: values (doubles on the 0..255 scale) as the samples of
// a PNG row, png8_sample or png16_sample of each, fast (png_samples.cpp).
#pragma once

#include <cstdint>

namespace fss::detail {

// Row `out` (width x channel_count x bit_depth / 8 bytes) as a PNG stores
// it: png8_sample (bit_depth 8) or png16_sample (16, big-endian) of each
// value of channels[0 .. channel_count - 1] (1 or 3 rows of `width` values),
// interleaved. `scratch` has room for width x channel_count samples. Runs
// the code compiled for AVX2 when the processor has it: the same samples
// (tested against the portable code).
void store_sample_row(const double* const* channels, int channel_count, int width, int bit_depth,
                      std::uint16_t* scratch, std::uint8_t* out);

// The same with the code for any x86-64 processor (SSE2), and whether
// store_sample_row runs the AVX2 code here: for the tests.
void store_sample_row_portable(const double* const* channels, int channel_count, int width,
                               int bit_depth, std::uint16_t* scratch, std::uint8_t* out);
bool sample_rows_use_avx2();

}  // namespace fss::detail
