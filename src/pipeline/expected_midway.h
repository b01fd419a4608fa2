// The tie expectation of RMSE_CI for one channel (docs/method.md §5), for
// metrics.cpp. Internal to the library.
#pragma once

#include <cstddef>
#include <cstdint>

#include "pipeline/record_sort.h"

namespace fss::midway {

// One channel's window of an image: `height` rows of `width` values, row y
// starting at first + y * stride.
struct ChannelWindow {
  const double* first = nullptr;
  std::size_t stride = 0;
  std::uint32_t width = 0;
  std::uint32_t height = 0;

  std::size_t size() const { return std::size_t{width} * height; }
  const double* row(std::uint32_t y) const { return first + y * stride; }
};

// sum over the pixels p of E[(a'_p - b'_p)^2], a' and b' the midway
// equalizations of windows a and b (of the same size), over independent
// uniform orders of each group of equal values of a and of b:
//   sum_G m2_G + sum_H m2_H + sum_p (B_G - B_H)^2,
// G and H the groups of a and b holding p, B the mean of mid_i over a
// group's ranks, m2 the sum of squared deviations of mid_i from B. Each sum
// is taken in an order fixed by the values alone: a's groups in rank order,
// b's groups in rank order, the pixels in b's rank order (equal b values in
// the order of a's groups), each group's mid_i in rank order. `records`
// holds a.size() records of scratch; `workers` (1 or 2) threads share the
// work, with the same result.
double expected_midway_sum(const ChannelWindow& a, const ChannelWindow& b, Record* records,
                           int workers);

}  // namespace fss::midway
