// Writes a deterministic synthetic RGB test image (edges, ramps, texture) of
// the requested size, for the benchmark's large case.
// Usage: make_image WIDTH HEIGHT OUT.png
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "fss/core/image.h"
#include "fss/io/png_io.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: make_image WIDTH HEIGHT OUT.png\n");
    return 2;
  }
  const int width = std::atoi(argv[1]);
  const int height = std::atoi(argv[2]);
  if (width < 1 || height < 1) {
    std::fprintf(stderr, "make_image: WIDTH and HEIGHT must be positive integers\n");
    return 2;
  }
  fss::Image image(width, height, 3);
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
  const auto bytes = fss::encode_png8(image);
  std::ofstream out(argv[3], std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "make_image: cannot write %s\n", argv[3]);
    return 1;
  }
  return 0;
}
