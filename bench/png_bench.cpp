// Times the PNG encoding of fssim's image outputs: each PNG given is decoded
// (to the doubles fssim encodes) and encoded again REPS times, 8-bit from
// doubles (encode_png, what restored.png costs), 8-bit from samples
// (encode_png8_samples, observed.png from an ObservedPng8) and 16-bit; then
// all of them at once on THREADS threads, as fssim's outputs are made
// (parallel_for_each, one file a thread at a time). Prints medians of wall
// and process CPU time, the encoded size and a hash of the bytes (the same
// hash on every run and thread count: the encoding is deterministic).
// Usage: png_bench [--reps N] [--threads N] FILE.png...
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/parallel.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"

namespace {

using Bytes = std::vector<std::uint8_t>;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// FNV-1a of the bytes: enough to tell two encodings apart.
std::uint64_t hash(const Bytes& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::uint8_t b : bytes) h = (h ^ b) * 0x100000001b3ULL;
  return h;
}

struct Timing {
  double wall = 0.0;
  double cpu = 0.0;
  std::size_t size = 0;
  std::uint64_t hash = 0;
};

// Medians over `reps` runs of `encode`; the total size and a hash of its
// last results.
Timing measure(int reps, const std::function<std::vector<Bytes>()>& encode) {
  std::vector<double> walls, cpus;
  std::vector<Bytes> files;
  for (int r = 0; r < reps; ++r) {
    files.clear();
    const double wall = wall_seconds(), cpu = cpu_seconds();
    files = encode();
    walls.push_back(wall_seconds() - wall);
    cpus.push_back(cpu_seconds() - cpu);
  }
  Timing timing{median(walls), median(cpus), 0, 0};
  for (const Bytes& bytes : files) {
    timing.size += bytes.size();
    timing.hash = timing.hash * 31 + hash(bytes);
  }
  return timing;
}

void print(const char* what, const std::string& name, const Timing& t) {
  std::printf("%-18s %-28s wall %8.2f ms  cpu %8.2f ms  %10zu bytes  hash %016llx\n", what,
              name.c_str(), 1e3 * t.wall, 1e3 * t.cpu, t.size,
              static_cast<unsigned long long>(t.hash));
}

// A list of one file, moved in (an initializer list would copy it).
std::vector<Bytes> one(Bytes bytes) {
  std::vector<Bytes> files;
  files.push_back(std::move(bytes));
  return files;
}

// The samples encode_png8 stores: interleaved, png8_sample of each value.
Bytes samples8(const fss::Image& image) {
  Bytes samples(image.data.size());
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) {
        samples[(static_cast<std::size_t>(y) * image.width + x) * image.channels + c] =
            fss::png8_sample(image.at(c, y, x));
      }
    }
  }
  return samples;
}

}  // namespace

int main(int argc, char** argv) {
  int reps = 5, threads = 2;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
      reps = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      paths.emplace_back(argv[i]);
    }
  }
  if (paths.empty() || reps < 1 || threads < 1) {
    std::fprintf(stderr, "usage: png_bench [--reps N] [--threads N] FILE.png...\n");
    return 2;
  }
  std::vector<fss::Image> images;
  images.reserve(paths.size());
  for (const std::string& path : paths) images.push_back(fss::read_png(path));
  for (std::size_t i = 0; i < images.size(); ++i) {
    const fss::Image& image = images[i];
    const Bytes samples = samples8(image);
    print("8-bit, doubles", paths[i], measure(reps, [&] { return one(fss::encode_png8(image)); }));
    print(
        "8-bit, samples", paths[i], measure(reps, [&] {
          return one(fss::encode_png8_samples(image.width, image.height, image.channels, samples));
        }));
    print("16-bit, doubles", paths[i],
          measure(reps, [&] { return one(fss::encode_png(image, fss::PngDepth::k16)); }));
  }
  // All at once, as fssim makes its outputs.
  const Timing all = measure(reps, [&] {
    std::vector<Bytes> made(images.size());
    fss::parallel_for_each(static_cast<int>(images.size()), threads,
                           [&](int i) { made[i] = fss::encode_png8(images[i]); });
    return made;
  });
  print("all, 8-bit", std::to_string(threads) + " thread(s)", all);
  return 0;
}
