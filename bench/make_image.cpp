// Writes a deterministic synthetic RGB test image (edges, ramps, texture) of
// the requested size, for the benchmark's large case.
// Usage: make_image WIDTH HEIGHT OUT.png
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "synthetic_image.h"

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
  const fss::Image image = fss::bench::synthetic_test_image(width, height);
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
