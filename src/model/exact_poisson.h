// An exact Poisson sampler for any mean (docs/method.md §6c): the grouped
// frames of the aggregated noise draw one variate of their summed intensity.
#pragma once

#include <span>

#include "model/noise_stream.h"

namespace fss {

// Means below this are drawn by inversion, the others by transformed rejection.
inline constexpr double kInversionLimit = 10.0;

// A Poisson variate of mean `mean`, exact for every mean (up to the rounding
// of double arithmetic): 0 for mean <= 0 (no draw), the mean itself when it is
// not finite (no draw). Below kInversionLimit, inversion by sequential search
// from 0 (one uniform); above, Hörmann's PTRS transformed rejection (two
// uniforms a try, about 1.1 tries).
double exact_poisson_variate(double mean, RandomStream& stream);

// out[x] += scale * P[x], P[x] ~ Poisson(mean[x]) by the same algorithm as
// exact_poisson_variate, for every x, but with the uniforms in another
// order, so that the first tries vectorize: for each block of 256 pixels,
// two uniforms a pixel (U, then V) in pixel order, PTRS's first tries of the
// whole block, then, in pixel order, the pixels they did not settle (an
// inversion from its U, or PTRS's slow test and further tries), whose further
// uniforms follow in the stream. Every pixel, even of mean 0, takes its two.
void add_exact_poisson_row(std::span<const double> mean, RandomStream& stream, double scale,
                           std::span<double> out);

// add_exact_poisson_row with every first try that the quick acceptance does
// not settle decided by the scalar slow test alone: the same bits, slower.
// add_exact_poisson_row decides those tries in bulk with bounded logarithms
// and a margin, and leaves the ones too close to call to the scalar test
// (docs/method.md §6c); the tests hold it to this one.
void add_exact_poisson_row_scalar(std::span<const double> mean, RandomStream& stream, double scale,
                                  std::span<double> out);

// ln P(X = k) for X ~ Poisson(mean), k >= 0 an integer, mean > 0: the
// acceptance test's target, exposed for the tests.
double poisson_log_pmf(double k, double mean);

}  // namespace fss
