// Tests of the PNG writer of the image outputs (src/io/png_write.cpp, what
// encode_png gives with PngCompression::kImage): the samples through libpng
// for many sizes, depths and channel counts, the chunks and their CRCs read
// here by hand and checked with zlib's CRC-32, the zlib stream inflated by
// zlib and unfiltered here, the bytes the same on every call and thread, a
// large image, and the errors.
#include "io/png_write.h"

#include "io/png_samples.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

// Values that exercise the rounding and clamping: out of range, NaN,
// infinities, every half of the 8-bit scale and its neighbours, and noise.
Image tricky_image(int width, int height, int channels, std::uint64_t seed) {
  Image image(width, height, channels);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> any(-30.0, 290.0);
  const std::vector<double> special = {std::numeric_limits<double>::quiet_NaN(),
                                       std::numeric_limits<double>::infinity(),
                                       -std::numeric_limits<double>::infinity(),
                                       -0.0,
                                       std::nextafter(0.5, 0.0),
                                       0.5,
                                       254.5,
                                       std::nextafter(255.0, 0.0),
                                       255.5,
                                       1e300,
                                       -1e300};
  std::size_t i = 0;
  for (double& v : image.data) {
    const std::uint64_t pick = rng() % 8;
    if (pick == 0) {
      v = special[i++ % special.size()];
    } else if (pick == 1) {
      const double half = static_cast<double>(rng() % 258) - 1.0 + 0.5;
      const int side = static_cast<int>(rng() % 3);
      v = side == 0 ? half : std::nextafter(half, side == 1 ? -1e9 : 1e9);
    } else if (pick == 2) {
      // A value whose 16-bit sample (value x 257) is at a half.
      const double half = (static_cast<double>(rng() % 65536) + 0.5) / 257.0;
      v = rng() % 2 == 0 ? half : std::nextafter(half, 1e9);
    } else {
      v = any(rng);
    }
  }
  return image;
}

// The samples a decoded PNG of `image` must hold (decode_png's scale: a
// 16-bit sample s reads as s / 257).
std::vector<double> expected_values(const Image& image, PngDepth depth) {
  std::vector<double> values(image.data.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = depth == PngDepth::k16 ? png16_sample(image.data[i]) / 257.0
                                       : static_cast<double>(png8_sample(image.data[i]));
  }
  return values;
}

Image decode(const Bytes& png) { return decode_png(png.data(), png.size(), "test.png"); }

// ---------------------------------------------------------------------------
// The file as the PNG specification lays it out, read here without libpng.

struct Chunk {
  std::string type;
  Bytes data;
};

// The chunks of `png`, after checking the signature, every length and every
// CRC (zlib's crc32 of type and data), and that nothing follows IEND.
std::vector<Chunk> read_chunks(const Bytes& png) {
  static const std::uint8_t kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  EXPECT_GE(png.size(), 8u);
  EXPECT_EQ(std::memcmp(png.data(), kSignature, 8), 0) << "signature";
  std::vector<Chunk> chunks;
  std::size_t at = 8;
  while (at < png.size()) {
    if (png.size() - at < 12) {
      ADD_FAILURE() << "truncated chunk at byte " << at;
      break;
    }
    const std::uint32_t length = be32(&png[at]);
    if (length > png.size() - at - 12) {
      ADD_FAILURE() << "chunk longer than the file at byte " << at;
      break;
    }
    Chunk chunk;
    chunk.type.assign(reinterpret_cast<const char*>(&png[at + 4]), 4);
    chunk.data.assign(png.begin() + static_cast<std::ptrdiff_t>(at + 8),
                      png.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
    const auto crc = static_cast<std::uint32_t>(crc32(0L, &png[at + 4], 4 + length));
    EXPECT_EQ(be32(&png[at + 8 + length]), crc) << chunk.type << " chunk at byte " << at;
    chunks.push_back(std::move(chunk));
    at += 12 + length;
    if (chunks.back().type == "IEND") break;
  }
  EXPECT_EQ(at, png.size()) << "bytes after IEND";
  return chunks;
}

// The zlib stream of the IDAT chunks inflated by zlib, which checks the
// header, the deflate blocks and the Adler-32; the stream must end exactly
// at the end of the last IDAT.
Bytes inflate_idat(const std::vector<Chunk>& chunks, std::size_t expected_size) {
  Bytes stream;
  for (const Chunk& chunk : chunks) {
    if (chunk.type == "IDAT") stream.insert(stream.end(), chunk.data.begin(), chunk.data.end());
  }
  EXPECT_GE(stream.size(), 6u);
  if (stream.size() < 6) return {};
  EXPECT_EQ(stream[0], 0x78) << "CMF: deflate with a 32 KiB window";
  EXPECT_EQ((stream[0] * 256 + stream[1]) % 31, 0) << "FCHECK";
  EXPECT_EQ(stream[1] & 0x20, 0) << "no preset dictionary";
  Bytes out(expected_size + 1);  // one more: the stream must not hold more
  z_stream z{};
  EXPECT_EQ(inflateInit(&z), Z_OK);
  z.next_in = stream.data();
  z.avail_in = static_cast<uInt>(stream.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(inflate(&z, Z_FINISH), Z_STREAM_END) << (z.msg ? z.msg : "");
  EXPECT_EQ(z.avail_in, 0u) << "bytes after the end of the zlib stream";
  EXPECT_EQ(z.total_out, expected_size);
  out.resize(z.total_out);
  inflateEnd(&z);
  return out;
}

// PNG's predictor of filter `type` from the bytes left (a), above (b) and
// above left (c), written here from the specification.
int predictor(int type, int a, int b, int c) {
  switch (type) {
    case 1:
      return a;
    case 2:
      return b;
    case 3:
      return (a + b) / 2;
    case 4: {
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
    }
    default:
      return 0;
  }
}

// The rows of the inflated stream unfiltered, without their filter bytes.
Bytes unfilter(const Bytes& filtered, std::size_t row_bytes, std::size_t pixel_bytes) {
  const std::size_t rows = filtered.size() / (row_bytes + 1);
  Bytes out(rows * row_bytes);
  const Bytes zeros(row_bytes, 0);
  for (std::size_t y = 0; y < rows; ++y) {
    const std::uint8_t type = filtered[y * (row_bytes + 1)];
    EXPECT_LE(type, 4) << "filter type of row " << y;
    const std::uint8_t* in = &filtered[y * (row_bytes + 1) + 1];
    std::uint8_t* row = &out[y * row_bytes];
    const std::uint8_t* up = y == 0 ? zeros.data() : row - row_bytes;
    for (std::size_t i = 0; i < row_bytes; ++i) {
      const int a = i >= pixel_bytes ? row[i - pixel_bytes] : 0;
      const int c = i >= pixel_bytes ? up[i - pixel_bytes] : 0;
      row[i] = static_cast<std::uint8_t>(in[i] + predictor(type, a, up[i], c));
    }
  }
  return out;
}

// The samples as the PNG must store them (png8_sample or png16_sample,
// big-endian), interleaved.
Bytes stored_samples(const Image& image, PngDepth depth) {
  Bytes out;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) {
        if (depth == PngDepth::k16) {
          const std::uint16_t s = png16_sample(image.at(c, y, x));
          out.push_back(static_cast<std::uint8_t>(s >> 8));
          out.push_back(static_cast<std::uint8_t>(s));
        } else {
          out.push_back(png8_sample(image.at(c, y, x)));
        }
      }
    }
  }
  return out;
}

// Checks everything above on the PNG of `image`.
void check_file_structure(const Bytes& png, const Image& image, PngDepth depth) {
  const std::vector<Chunk> chunks = read_chunks(png);
  ASSERT_GE(chunks.size(), 3u);
  ASSERT_EQ(chunks.front().type, "IHDR");
  const Bytes& ihdr = chunks.front().data;
  ASSERT_EQ(ihdr.size(), 13u);
  EXPECT_EQ(be32(&ihdr[0]), static_cast<std::uint32_t>(image.width));
  EXPECT_EQ(be32(&ihdr[4]), static_cast<std::uint32_t>(image.height));
  EXPECT_EQ(ihdr[8], depth == PngDepth::k16 ? 16 : 8);
  EXPECT_EQ(ihdr[9], image.channels == 3 ? 2 : 0);
  EXPECT_EQ(ihdr[10], 0);
  EXPECT_EQ(ihdr[11], 0);
  EXPECT_EQ(ihdr[12], 0);
  EXPECT_EQ(chunks.back().type, "IEND");
  EXPECT_TRUE(chunks.back().data.empty());
  for (std::size_t i = 1; i + 1 < chunks.size(); ++i) {
    EXPECT_EQ(chunks[i].type, "IDAT") << "chunk " << i;
    EXPECT_FALSE(chunks[i].data.empty()) << "empty IDAT " << i;
  }
  const std::size_t sample_bytes = depth == PngDepth::k16 ? 2 : 1;
  const std::size_t pixel_bytes = sample_bytes * image.channels;
  const std::size_t row_bytes = pixel_bytes * image.width;
  const Bytes filtered = inflate_idat(chunks, (row_bytes + 1) * image.height);
  ASSERT_EQ(filtered.size(), (row_bytes + 1) * image.height);
  for (int y = 0; y < image.height; ++y) {
    ASSERT_EQ(filtered[y * (row_bytes + 1)], 3) << "the average filter, row " << y;
  }
  EXPECT_TRUE(unfilter(filtered, row_bytes, pixel_bytes) == stored_samples(image, depth));
}

// ---------------------------------------------------------------------------

class PngWriteSizes : public ::testing::TestWithParam<std::tuple<PngDepth, int>> {};

// Every width from 1 to 40, then widths around powers of two and odd row
// lengths, heights 1 to 3 and 17: the samples read back by libpng are
// png8_sample or png16_sample of the values, the file is laid out as the
// specification says, and the 8-bit samples given directly give the same file.
TEST_P(PngWriteSizes, RoundTripThroughLibpngAndTheSpecification) {
  const auto [depth, channels] = GetParam();
  std::vector<int> widths;
  for (int w = 1; w <= 40; ++w) widths.push_back(w);
  for (const int w : {63, 64, 65, 127, 255, 257, 1000, 1023, 1025}) widths.push_back(w);
  std::uint64_t seed = 1;
  for (const int width : widths) {
    for (const int height : {1, 2, 3, 17}) {
      const Image image = tricky_image(width, height, channels, seed++);
      const Bytes png = encode_png(image, depth);
      const Image decoded = decode(png);
      ASSERT_EQ(decoded.width, width);
      ASSERT_EQ(decoded.height, height);
      ASSERT_EQ(decoded.channels, channels);
      ASSERT_TRUE(decoded.data == expected_values(image, depth)) << width << " x " << height;
      check_file_structure(png, image, depth);
      if (HasFatalFailure()) return;
      // The rows given one by one through fill_row: the same file.
      const Bytes filled = encode_png(
          width, height, channels,
          [&](int c, int y, double* row) {
            std::copy(image.row(c, y), image.row(c, y) + width, row);
          },
          depth);
      ASSERT_TRUE(filled == png) << width << " x " << height;
      if (depth == PngDepth::k8) {
        const Bytes samples = stored_samples(image, depth);
        ASSERT_TRUE(encode_png8_samples(width, height, channels, samples) == png);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DepthsAndChannels, PngWriteSizes,
                         ::testing::Combine(::testing::Values(PngDepth::k8, PngDepth::k16),
                                            ::testing::Values(1, 3)),
                         [](const auto& info) {
                           return "depth" + to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) == 3 ? "_rgb" : "_gray");
                         });

// The conversion of values to samples is png8_sample and png16_sample for
// every half of both scales, its neighbours and many other values.
TEST(PngWrite, SamplesAreThoseOfPng8SampleAndPng16Sample) {
  std::vector<double> values = {std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(),
                                4.9e-324,
                                -0.0,
                                std::nextafter(0.5, 0.0),
                                0.5,
                                255.49,
                                255.5,
                                256.0,
                                65535.0 / 257.0 + 1e-9};
  for (int k = -2; k <= 258; ++k) {
    const double half = k + 0.5;
    values.insert(values.end(), {half, std::nextafter(half, -1e9), std::nextafter(half, 1e9)});
  }
  for (int k = 0; k < 65536; k += 7) {
    const double half = (k + 0.5) / 257.0;
    values.insert(values.end(), {half, std::nextafter(half, -1e9), std::nextafter(half, 1e9)});
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> any(-20.0, 280.0);
  for (int i = 0; i < 100000; ++i) values.push_back(any(rng));
  // Rows of 1000 (libpng reads sides up to kMaxImageSide), the last one
  // completed with zeros.
  const int rows = static_cast<int>((values.size() + 999) / 1000);
  values.resize(static_cast<std::size_t>(rows) * 1000, 0.0);
  Image image(1000, rows, 1);
  image.data.assign(values.begin(), values.end());
  for (const PngDepth depth : {PngDepth::k8, PngDepth::k16}) {
    const Image decoded = decode(encode_png(image, depth));
    const std::vector<double> expected = expected_values(image, depth);
    for (std::size_t i = 0; i < values.size(); ++i) {
      ASSERT_EQ(decoded.data[i], expected[i]) << "value " << values[i] << ", " << to_string(depth);
    }
    // The portable code too, where the encoder ran the AVX2 code.
    const int bits = depth == PngDepth::k16 ? 16 : 8;
    const Bytes stored = stored_samples(image, depth);
    Bytes row(static_cast<std::size_t>(image.width) * bits / 8);
    std::vector<std::uint16_t> scratch(static_cast<std::size_t>(image.width));
    for (int y = 0; y < image.height; ++y) {
      const double* values_row = image.row(0, y);
      detail::store_sample_row_portable(&values_row, 1, image.width, bits, scratch.data(),
                                        row.data());
      ASSERT_TRUE(std::equal(row.begin(), row.end(), stored.begin() + y * row.size())) << y;
    }
  }
}

// The samples of a row from the code compiled for AVX2 (when the processor
// has it: store_sample_row) and from the portable code, against
// png8_sample and png16_sample.
TEST(PngWrite, SampleRowsAreTheSameFromEveryCode) {
  if (!detail::sample_rows_use_avx2()) std::printf("note: no AVX2 here, one code compared\n");
  for (const int width : {1, 2, 3, 7, 15, 16, 17, 31, 33, 64, 100, 1001}) {
    for (const int channels : {1, 3}) {
      const Image image = tricky_image(width, 1, channels, static_cast<std::uint64_t>(width));
      std::vector<const double*> rows(static_cast<std::size_t>(channels));
      for (int c = 0; c < channels; ++c) rows[c] = image.row(c, 0);
      for (const int bits : {8, 16}) {
        const std::size_t size = static_cast<std::size_t>(width) * channels * (bits / 8);
        Bytes fast(size + 1, 0xA5), portable(size + 1, 0xA5);  // one byte more: untouched
        std::vector<std::uint16_t> scratch(static_cast<std::size_t>(width) * channels);
        detail::store_sample_row(rows.data(), channels, width, bits, scratch.data(), fast.data());
        detail::store_sample_row_portable(rows.data(), channels, width, bits, scratch.data(),
                                          portable.data());
        const Bytes expected = stored_samples(image, bits == 16 ? PngDepth::k16 : PngDepth::k8);
        EXPECT_TRUE(Bytes(fast.begin(), fast.end() - 1) == expected) << width << " " << bits;
        EXPECT_TRUE(portable == fast) << width << " x " << channels << ", " << bits << " bits";
        EXPECT_EQ(fast.back(), 0xA5);
      }
    }
  }
}

TEST(PngWrite, AverageFilterIsTheSpecifications) {
  std::mt19937_64 rng(9);
  for (const std::size_t pixel_bytes : {1u, 2u, 3u, 6u}) {
    for (const std::size_t row_bytes : {pixel_bytes, 2 * pixel_bytes, 37 * pixel_bytes}) {
      Bytes above(row_bytes), row(row_bytes), out(row_bytes);
      for (auto& b : above) b = static_cast<std::uint8_t>(rng());
      for (auto& b : row) b = static_cast<std::uint8_t>(rng());
      detail::average_filter(row.data(), above.data(), row_bytes, pixel_bytes, out.data());
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int left = i >= pixel_bytes ? row[i - pixel_bytes] : 0;
        ASSERT_EQ(out[i], static_cast<std::uint8_t>(row[i] - (left + above[i]) / 2))
            << pixel_bytes << " " << row_bytes << " " << i;
      }
    }
  }
}

// Many blocks of rows and IDAT chunks, and a zlib stream of many deflate
// blocks: a noisy 4000 x 2500 RGB image (30 MB of rows, about as
// incompressible as a restoration gets), read back by libpng and by zlib.
TEST(PngWrite, LargeImage) {
  // Under AddressSanitizer 1000 x 700 (2 MB of rows): still 8 blocks of rows and IDAT chunks.
  const bool asan = test::kAddressSanitizer;
  const Image image = tricky_image(asan ? 1000 : 4000, asan ? 700 : 2500, 3, 77);
  const Bytes png = encode_png(image, PngDepth::k8);
  EXPECT_GT(png.size(), std::size_t{asan ? 1 : 4} << 20);
  const Image decoded = decode(png);
  ASSERT_TRUE(decoded.data == expected_values(image, PngDepth::k8));
  check_file_structure(png, image, PngDepth::k8);
  // 11 pixels wide and 65536 rows tall (the largest side libpng reads
  // here): rows of 23 bytes, so that the rows span several blocks.
  const Image tall = tricky_image(11, 65536, 1, 78);
  const Bytes tall_png = encode_png(tall, PngDepth::k16);
  ASSERT_TRUE(decode(tall_png).data == expected_values(tall, PngDepth::k16));
  check_file_structure(tall_png, tall, PngDepth::k16);
}

// The same image gives the same bytes every time, encoded alone or while
// other images are encoded on other threads, as fssim's outputs are.
TEST(PngWrite, SameBytesEveryTimeAndOnAnyThread) {
  std::vector<Image> images;
  images.reserve(6);
  for (int i = 0; i < 6; ++i) images.push_back(tricky_image(301 + 97 * i, 211, i % 2 ? 3 : 1, i));
  std::vector<Bytes> alone;
  alone.reserve(images.size());
  for (const Image& image : images) {
    alone.push_back(encode_png(image, PngDepth::k8));
    EXPECT_TRUE(encode_png(image, PngDepth::k8) == alone.back());
  }
  for (const int threads : {1, 2, 4}) {
    std::vector<Bytes> made(images.size());
    parallel_for_each(static_cast<int>(images.size()), threads,
                      [&](int i) { made[i] = encode_png(images[i], PngDepth::k8); });
    for (std::size_t i = 0; i < images.size(); ++i) {
      EXPECT_TRUE(made[i] == alone[i]) << "image " << i << ", " << threads << " threads";
    }
  }
  // The std::string of an output file holds the same bytes.
  const std::string as_file = detail::encode_png_string(images[1], PngDepth::k8);
  EXPECT_TRUE(Bytes(as_file.begin(), as_file.end()) == alone[1]);
}

// An exception of the rows' source goes through, and nothing is returned.
TEST(PngWrite, ExceptionOfTheRowsGoesThrough) {
  EXPECT_THROW(encode_png(
                   40, 30, 1,
                   [](int, int y, double* row) {
                     if (y == 20) throw std::logic_error("row 20");
                     std::fill(row, row + 40, 1.0);
                   },
                   PngDepth::k8),
               std::logic_error);
}

// Out of memory while encoding: a runtime fss::Error saying so.
TEST(PngWriteDeathTest, OutOfMemoryIsAnError) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "RLIMIT_AS cannot be used under AddressSanitizer";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const Image image(3000, 3000, 3, 100.0);  // 27 M samples, allocated before the limit
        test::limit_address_space(std::size_t{1} << 20);
        try {
          encode_png(image, PngDepth::k8);
        } catch (const Error& e) {
          const std::string message = e.what();
          std::_Exit(e.kind() == ErrorKind::kRuntime &&
                             message.find("PNG encoding") != std::string::npos &&
                             message.find("out of memory") != std::string::npos
                         ? 0
                         : 3);
        }
        std::_Exit(4);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace fss
