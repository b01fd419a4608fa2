// libFuzzer target: fss::decode_png on arbitrary bytes, then the image it
// gives encoded again (the writer of the image outputs, src/io/png_write.cpp)
// and decoded back. An fss::Error is the expected end for most inputs; any
// other exception escaping, a crash, a sanitizer report, a leak, a decoded
// image that breaks the conventions of image.h, or a round trip that changes
// a sample is a bug. In this build (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION)
// the reader ignores CRCs, so that mutated headers get past them.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"

namespace {

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

// A file may rightly hold an image of gigabytes of pixels (a deflate stream
// expands up to 1032 times); how much memory to allow is not this target's
// question. It skips inputs whose IHDR declares more than 2^24 pixels unless
// the file is too small to hold them, so that their refusal is still fuzzed.
bool legitimately_huge(const std::uint8_t* data, std::size_t size) {
  if (size < 8 + 8 + 13) return false;
  const std::uint8_t* ihdr = data + 16;  // after the signature, length and type
  const std::uint64_t pixels = std::uint64_t{be32(ihdr)} * be32(ihdr + 4);
  const int depth = ihdr[8];
  const int color_type = ihdr[9];
  const int samples = color_type == 2 ? 3 : color_type == 4 ? 2 : color_type == 6 ? 4 : 1;
  const std::uint64_t stored_bytes = pixels * static_cast<std::uint64_t>(depth * samples) / 8;
  return pixels > (std::uint64_t{1} << 24) && stored_bytes <= 1032 * (std::uint64_t{size} + 1);
}

// Every decoded image comes back from a 16-bit PNG exactly (a sample s reads
// as s / 257, which png16_sample turns back into s), and from an 8-bit one
// when its values are whole (8-bit sources).
void check_round_trips(const fss::Image& image) {
  const auto same = [&](const std::vector<std::uint8_t>& png) {
    const fss::Image back = fss::decode_png(png.data(), png.size(), "round-trip.png");
    return back.width == image.width && back.height == image.height &&
           back.channels == image.channels && back.data == image.data;
  };
  if (!same(fss::encode_png(image, fss::PngDepth::k16))) __builtin_trap();
  for (const double value : image.data) {
    if (value != std::floor(value)) return;
  }
  if (!same(fss::encode_png(image, fss::PngDepth::k8))) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (legitimately_huge(data, size)) return 0;
  fss::Image image;
  try {
    image = fss::decode_png(data, size, "fuzz.png");
  } catch (const fss::Error&) {
    return 0;  // a damaged or hostile file, refused with a message: the expected end
  }
  const bool valid_size = image.width >= 1 && image.height >= 1 &&
                          image.width <= fss::kMaxImageSide && image.height <= fss::kMaxImageSide &&
                          (image.channels == 1 || image.channels == 3) &&
                          image.data.size() == image.plane_size() * image.channels;
  if (!valid_size) __builtin_trap();
  for (const double value : image.data) {
    if (!(value >= 0.0 && value <= 255.0)) __builtin_trap();
  }
  // Out of the try: an error of the encoder, or of decoding what it wrote,
  // is a bug (libFuzzer reports the exception).
  check_round_trips(image);
  return 0;
}
