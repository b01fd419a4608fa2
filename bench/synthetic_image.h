// The deterministic synthetic RGB test image of the benchmark's large case
// (edges, ramps, texture), on the 0..255 scale before 8-bit encoding:
// make_image writes it as a PNG, micro_bench rounds it as reading that PNG
// back would.
#pragma once

#include <cmath>
#include <cstdint>

#include "fss/core/image.h"

namespace fss::bench {

inline Image synthetic_test_image(int width, int height) {
  Image image(width, height, 3);
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // LCG texture
      const double texture = static_cast<double>(state >> 40) / (1 << 24) * 30.0 - 15.0;
      for (int c = 0; c < 3; ++c) {
        double v = 30.0 + 180.0 * ((x + c * 97) % width) / width;
        if (((x / 61) + (y / 47) + c) % 2 == 0) v += 35.0;
        v += 20.0 * std::sin(0.013 * y + 0.7 * c) + texture;
        image.at(c, y, x) = v;
      }
    }
  }
  return image;
}

}  // namespace fss::bench
