// libFuzzer target: fss::decode_tiff on arbitrary bytes. An fss::Error is the
// expected end for most inputs; any other exception escaping, a crash, a
// sanitizer report, a leak, or a decoded image that breaks the conventions
// of image.h is a bug. A decoded image is also written as a float TIFF and
// read back: its values must come back as their nearest floats.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"

namespace {

// A file may rightly hold gigabytes of pixels; how much memory to allow is
// not this target's question: decoding over 256 MiB is refused from the
// header (a kLimit error), which is fuzzed too.
constexpr std::size_t kMaxDecodeBytes = std::size_t{256} << 20;

bool follows_conventions(const fss::Image& image) {
  const bool valid_size = image.width >= 1 && image.height >= 1 &&
                          image.width <= fss::kMaxImageSide && image.height <= fss::kMaxImageSide &&
                          (image.channels == 1 || image.channels == 3) &&
                          image.data.size() == image.plane_size() * image.channels;
  if (!valid_size) return false;
  for (const double value : image.data) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

void check_float_round_trip(const fss::Image& image) {
  if (image.plane_size() > (std::size_t{1} << 16)) return;
  const std::vector<std::uint8_t> bytes = fss::encode_tiff_float(image);
  const fss::Image back = fss::decode_tiff(bytes.data(), bytes.size(), "round-trip.tif");
  if (back.data.size() != image.data.size()) __builtin_trap();
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    if (back.data[i] != static_cast<double>(static_cast<float>(image.data[i]))) __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const fss::Image image = fss::decode_tiff(data, size, "fuzz.tif", kMaxDecodeBytes);
    if (!follows_conventions(image)) __builtin_trap();
    check_float_round_trip(image);
  } catch (const fss::Error&) {
    // A damaged or hostile file, refused with a message: the expected end.
  }
  return 0;
}
