// Tests of PNG reading and 8-bit encoding (png_io.h): round trips, every
// colour type and bit depth written here with libpng itself, and the errors of
// damaged or hostile files.
#include "fss/io/png_io.h"

#include <gtest/gtest.h>
#include <png.h>
#include <sys/resource.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Bytes = std::vector<std::uint8_t>;

// ---------------------------------------------------------------------------
// Writing test PNGs with libpng.

using test::PngSpec;

Bytes write_png(const PngSpec& spec) { return test::craft_png(spec); }

// Packs samples of `bits` bits (1, 2, 4, 8 or 16) into a PNG row.
Bytes pack_row(const std::vector<int>& samples, int bits) {
  Bytes row;
  if (bits == 16) {
    for (int s : samples) {
      row.push_back(static_cast<std::uint8_t>(s >> 8));
      row.push_back(static_cast<std::uint8_t>(s & 0xff));
    }
    return row;
  }
  if (bits == 8) {
    for (int s : samples) row.push_back(static_cast<std::uint8_t>(s));
    return row;
  }
  const int per_byte = 8 / bits;
  row.assign((samples.size() + per_byte - 1) / per_byte, 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int shift = 8 - bits * (static_cast<int>(i % per_byte) + 1);
    row[i / per_byte] |= static_cast<std::uint8_t>(samples[i] << shift);
  }
  return row;
}

Image decode(const Bytes& bytes, const std::string& name = "test.png") {
  return decode_png(bytes.data(), bytes.size(), name);
}

std::string as_string(const Bytes& bytes) { return {bytes.begin(), bytes.end()}; }

// ---------------------------------------------------------------------------
// Chunk surgery for damaged files.

struct Chunk {
  std::string type;
  Bytes data;
  std::uint32_t crc = 0;  // as stored
};

std::uint32_t read_be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

void append_be32(Bytes* out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out->push_back(static_cast<std::uint8_t>(v >> shift));
}

std::uint32_t chunk_crc(const Chunk& chunk) {
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(chunk.type.data()), 4);
  crc = crc32(crc, chunk.data.data(), static_cast<uInt>(chunk.data.size()));
  return static_cast<std::uint32_t>(crc);
}

std::vector<Chunk> split_chunks(const Bytes& png) {
  std::vector<Chunk> chunks;
  std::size_t pos = 8;
  while (pos + 12 <= png.size()) {
    const std::uint32_t length = read_be32(&png[pos]);
    Chunk chunk;
    chunk.type.assign(reinterpret_cast<const char*>(&png[pos + 4]), 4);
    chunk.data.assign(png.begin() + static_cast<std::ptrdiff_t>(pos + 8),
                      png.begin() + static_cast<std::ptrdiff_t>(pos + 8 + length));
    chunk.crc = read_be32(&png[pos + 8 + length]);
    chunks.push_back(chunk);
    pos += 12 + length;
  }
  return chunks;
}

Bytes join_chunks(const std::vector<Chunk>& chunks) {
  Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  for (const Chunk& chunk : chunks) {
    append_be32(&out, static_cast<std::uint32_t>(chunk.data.size()));
    out.insert(out.end(), chunk.type.begin(), chunk.type.end());
    out.insert(out.end(), chunk.data.begin(), chunk.data.end());
    append_be32(&out, chunk.crc);
  }
  return out;
}

Chunk* find_chunk(std::vector<Chunk>* chunks, const std::string& type) {
  for (Chunk& chunk : *chunks) {
    if (chunk.type == type) return &chunk;
  }
  return nullptr;
}

// A valid 8-bit RGB PNG with incompressible content, so that its IDAT is large.
Bytes valid_noisy_png() { return encode_png8(test::make_test_image(64, 48, 3, 7)); }

// A valid PNG whose IHDR declares the given size (the CRC is recomputed).
Bytes png_with_declared_size(std::uint32_t width, std::uint32_t height) {
  std::vector<Chunk> chunks = split_chunks(encode_png8(Image(4, 4, 1, 9.0)));
  Chunk* ihdr = find_chunk(&chunks, "IHDR");
  EXPECT_NE(ihdr, nullptr);
  Bytes data;
  append_be32(&data, width);
  append_be32(&data, height);
  std::copy(data.begin(), data.end(), ihdr->data.begin());
  ihdr->crc = chunk_crc(*ihdr);
  return join_chunks(chunks);
}

// ---------------------------------------------------------------------------
// Round trips through encode_png8.

TEST(EncodePng8, GrayRoundTripRoundsAndClamps) {
  const std::vector<double> values = {-3.0, 300.0, 12.5, 12.49, 0.0,   255.0,
                                      0.5,  254.5, -0.4, 127.6, 255.4, 1e9};
  const std::vector<double> expected = {0.0, 255.0, 13.0, 12.0,  0.0,   255.0,
                                        1.0, 255.0, 0.0,  128.0, 255.0, 255.0};
  Image image(4, 3, 1);
  image.data.assign(values.begin(), values.end());
  const Image decoded = decode(encode_png8(image));
  ASSERT_EQ(decoded.width, 4);
  ASSERT_EQ(decoded.height, 3);
  ASSERT_EQ(decoded.channels, 1);
  EXPECT_EQ(decoded.data, expected);
}

TEST(EncodePng8, RgbRoundTripKeepsChannelsApart) {
  Image image(3, 2, 3);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) image.at(c, y, x) = 100.0 * c + 10.0 * y + x + 0.3;
    }
  }
  image.at(0, 0, 0) = -3.0;
  image.at(1, 1, 2) = 300.0;
  image.at(2, 0, 1) = 12.5;
  image.at(2, 1, 0) = 12.49;
  const Image decoded = decode(encode_png8(image));
  ASSERT_EQ(decoded.width, 3);
  ASSERT_EQ(decoded.height, 2);
  ASSERT_EQ(decoded.channels, 3);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) {
        double want = 100.0 * c + 10.0 * y + x;  // the .3 rounds away
        if (c == 0 && y == 0 && x == 0) want = 0.0;
        if (c == 1 && y == 1 && x == 2) want = 255.0;
        if (c == 2 && y == 0 && x == 1) want = 13.0;
        if (c == 2 && y == 1 && x == 0) want = 12.0;
        want = std::min(want, 255.0);
        EXPECT_EQ(decoded.at(c, y, x), want) << "c=" << c << " y=" << y << " x=" << x;
      }
    }
  }
}

// png8_sample is the rounding and clamping rule spelled with std::round.
TEST(Png8Sample, EqualsClampedStdRound) {
  auto expected = [](double v) {
    const double r = std::clamp(std::round(v), 0.0, 255.0);
    return static_cast<std::uint8_t>(std::isnan(r) ? 0.0 : r);
  };
  std::vector<double> values = {0.0,
                                -0.0,
                                std::nextafter(0.5, 0.0),
                                0.5,
                                std::nextafter(0.5, 1.0),
                                1.5,
                                2.5,
                                std::nextafter(254.5, 0.0),
                                254.5,
                                std::nextafter(255.0, 0.0),
                                255.0,
                                255.49,
                                255.5,
                                256.0,
                                -0.5,
                                -0.49,
                                -1.5,
                                4.9e-324,
                                1e300,
                                -1e300,
                                std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::quiet_NaN()};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> any(-20.0, 280.0);
  for (int i = 0; i < 200000; ++i) values.push_back(any(rng));
  for (int k = -2; k <= 258; ++k) {  // every half and its neighbours
    const double half = k + 0.5;
    values.insert(values.end(), {half, std::nextafter(half, -1e9), std::nextafter(half, 1e9)});
  }
  for (const double v : values) ASSERT_EQ(png8_sample(v), expected(v)) << v;
}

// Both compressions hold the same pixels, and 8-bit samples encode as the
// same values given as doubles.
TEST(EncodePng8, CompressionsAndSampleInputKeepThePixels) {
  const Image image = test::make_test_image(37, 11, 3, 8);
  std::vector<std::uint8_t> samples(image.plane_size() * 3);
  for (int y = 0; y < 11; ++y) {
    for (int x = 0; x < 37; ++x) {
      for (int c = 0; c < 3; ++c) samples[(y * 37 + x) * 3 + c] = png8_sample(image.at(c, y, x));
    }
  }
  const Image expected = decode(encode_png8(image));
  for (const PngCompression compression : {PngCompression::kImage, PngCompression::kGraphics}) {
    EXPECT_EQ(decode(encode_png8(image, compression)).data, expected.data);
    EXPECT_EQ(decode(encode_png8_samples(37, 11, 3, samples, compression)).data, expected.data);
  }
  EXPECT_TRUE(encode_png8_samples(37, 11, 3, samples) == encode_png8(image));
  EXPECT_TRUE(test::throws_error(
      [&] { encode_png8_samples(37, 11, 3, std::span(samples).first(100)); }, ErrorKind::kUsage));
  EXPECT_TRUE(
      test::throws_error([&] { encode_png8_samples(37, 11, 2, samples); }, ErrorKind::kUsage));
}

TEST(EncodePng8, RefusesTwoChannels) {
  EXPECT_TRUE(test::throws_error([] { encode_png8(Image(2, 2, 2)); }, ErrorKind::kUsage));
}

// ---------------------------------------------------------------------------
// Decoding the formats a PNG may come in.

TEST(DecodePng, SixteenBitGrayIsDividedBy257Exactly) {
  const std::vector<int> samples = {0, 1, 256, 257, 12345, 32768, 65534, 65535};
  PngSpec spec;
  spec.width = 4;
  spec.height = 2;
  spec.bit_depth = 16;
  spec.color_type = PNG_COLOR_TYPE_GRAY;
  spec.rows = {pack_row({samples.begin(), samples.begin() + 4}, 16),
               pack_row({samples.begin() + 4, samples.end()}, 16)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 1);
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 2);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(image.data[i], samples[i] / 257.0) << "sample " << samples[i];
  }
}

TEST(DecodePng, SixteenBitRgb) {
  // pixel x: (r, g, b) = (1000 x + 1, 65535 - 77 x, 257 x)
  std::vector<int> samples;
  for (int x = 0; x < 5; ++x) {
    samples.push_back(1000 * x + 1);
    samples.push_back(65535 - 77 * x);
    samples.push_back(257 * x);
  }
  PngSpec spec;
  spec.width = 5;
  spec.height = 1;
  spec.bit_depth = 16;
  spec.color_type = PNG_COLOR_TYPE_RGB;
  spec.rows = {pack_row(samples, 16)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 3);
  ASSERT_EQ(image.width, 5);
  for (int x = 0; x < 5; ++x) {
    EXPECT_EQ(image.at(0, 0, x), (1000 * x + 1) / 257.0);
    EXPECT_EQ(image.at(1, 0, x), (65535 - 77 * x) / 257.0);
    EXPECT_EQ(image.at(2, 0, x), static_cast<double>(x));
  }
}

TEST(DecodePng, PaletteBecomesRgbWithThePaletteColours) {
  PngSpec spec;
  spec.width = 4;
  spec.height = 2;
  spec.bit_depth = 8;
  spec.color_type = PNG_COLOR_TYPE_PALETTE;
  spec.palette = {{10, 20, 30}, {255, 0, 128}, {1, 2, 3}, {200, 201, 202}};
  const std::vector<int> indices = {0, 1, 2, 3, 3, 3, 1, 0};
  spec.rows = {pack_row({indices.begin(), indices.begin() + 4}, 8),
               pack_row({indices.begin() + 4, indices.end()}, 8)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 3);
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 2);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      const png_color& colour = spec.palette[indices[y * 4 + x]];
      EXPECT_EQ(image.at(0, y, x), colour.red);
      EXPECT_EQ(image.at(1, y, x), colour.green);
      EXPECT_EQ(image.at(2, y, x), colour.blue);
    }
  }
}

TEST(DecodePng, GrayAlphaDropsAlpha) {
  // (gray, alpha) pairs; alpha 0 must not blank or premultiply the gray.
  const std::vector<int> samples = {7, 0, 100, 255, 200, 128, 255, 1};
  PngSpec spec;
  spec.width = 4;
  spec.height = 1;
  spec.color_type = PNG_COLOR_TYPE_GRAY_ALPHA;
  spec.rows = {pack_row(samples, 8)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 1);
  EXPECT_EQ(image.data, (std::vector<double>{7, 100, 200, 255}));
}

TEST(DecodePng, RgbaDropsAlpha) {
  const std::vector<int> samples = {1, 2, 3, 0, 40, 50, 60, 255, 250, 251, 252, 77};
  PngSpec spec;
  spec.width = 3;
  spec.height = 1;
  spec.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
  spec.rows = {pack_row(samples, 8)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 3);
  ASSERT_EQ(image.width, 3);
  for (int x = 0; x < 3; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(image.at(c, 0, x), samples[4 * x + c]);
  }
}

TEST(DecodePng, SixteenBitRgbaDropsAlpha) {
  const std::vector<int> samples = {65535, 0, 257, 0, 514, 1028, 2056, 65535};
  PngSpec spec;
  spec.width = 2;
  spec.height = 1;
  spec.bit_depth = 16;
  spec.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
  spec.rows = {pack_row(samples, 16)};
  const Image image = decode(write_png(spec));
  ASSERT_EQ(image.channels, 3);
  for (int x = 0; x < 2; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(image.at(c, 0, x), samples[4 * x + c] / 257.0);
  }
}

TEST(DecodePng, LowBitDepthGrayIsScaledTo255) {
  // Widths not a multiple of the samples per byte exercise the row padding;
  // libpng scales a b-bit gray g to g * 255 / (2^b - 1).
  struct Case {
    int bits;
    std::vector<int> samples;
    int scale;
  };
  const std::vector<Case> cases = {
      {1, {1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1}, 255},
      {2, {0, 1, 2, 3, 3, 2, 1}, 85},
      {4, {0, 1, 2, 7, 8, 14, 15, 5, 9}, 17},
  };
  for (const Case& c : cases) {
    PngSpec spec;
    spec.width = static_cast<int>(c.samples.size());
    spec.height = 2;
    spec.bit_depth = c.bits;
    spec.color_type = PNG_COLOR_TYPE_GRAY;
    std::vector<int> reversed(c.samples.rbegin(), c.samples.rend());
    spec.rows = {pack_row(c.samples, c.bits), pack_row(reversed, c.bits)};
    const Image image = decode(write_png(spec));
    ASSERT_EQ(image.channels, 1) << c.bits << "-bit";
    ASSERT_EQ(image.width, spec.width) << c.bits << "-bit";
    for (int x = 0; x < spec.width; ++x) {
      EXPECT_EQ(image.at(0, 0, x), c.samples[x] * c.scale) << c.bits << "-bit, x " << x;
      EXPECT_EQ(image.at(0, 1, x), reversed[x] * c.scale) << c.bits << "-bit, x " << x;
    }
  }
}

TEST(DecodePng, InterlacedEqualsNonInterlaced) {
  // 13 x 11 is not a multiple of the 8 x 8 Adam7 tile: every pass is partial.
  PngSpec spec;
  spec.width = 13;
  spec.height = 11;
  spec.color_type = PNG_COLOR_TYPE_RGB;
  for (int y = 0; y < spec.height; ++y) {
    std::vector<int> samples;
    for (int x = 0; x < spec.width; ++x) {
      for (int c = 0; c < 3; ++c) samples.push_back((y * 37 + x * 11 + c * 70) % 256);
    }
    spec.rows.push_back(pack_row(samples, 8));
  }
  const Image plain = decode(write_png(spec));
  spec.interlaced = true;
  const Bytes interlaced_bytes = write_png(spec);
  ASSERT_EQ(interlaced_bytes.size() > 28 ? interlaced_bytes[28] : 0, 1) << "IHDR interlace byte";
  const Image interlaced = decode(interlaced_bytes);
  ASSERT_EQ(interlaced.width, 13);
  ASSERT_EQ(interlaced.height, 11);
  ASSERT_EQ(interlaced.channels, 3);
  EXPECT_EQ(interlaced.data, plain.data);
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(interlaced.at(c, y, x), (y * 37 + x * 11 + c * 70) % 256);
      }
    }
  }
}

TEST(ReadPng, ReadsTheBundledImages) {
  // astronaut.png carries an iCCP chunk libpng warns about; warnings are not errors.
  const Image astronaut = read_png(test::source_path("data/astronaut.png"));
  EXPECT_EQ(astronaut.width, 512);
  EXPECT_EQ(astronaut.height, 512);
  EXPECT_EQ(astronaut.channels, 3);
  const Image camera = read_png(test::source_path("data/camera.png"));
  EXPECT_EQ(camera.width, 512);
  EXPECT_EQ(camera.height, 512);
  EXPECT_EQ(camera.channels, 1);
  for (const double v : camera.data) {
    ASSERT_TRUE(v >= 0.0 && v <= 255.0 && v == std::round(v)) << v;
  }
}

TEST(ReadPng, ReadsWhatItWasGivenFromAFile) {
  test::TempDir dir;
  const Image image = test::make_test_image(9, 5, 3, 3);
  const Bytes bytes = encode_png8(image);
  test::write_file(dir / "x.png", as_string(bytes));
  EXPECT_EQ(read_png(dir / "x.png").data, decode(bytes).data);
}

// ---------------------------------------------------------------------------
// Errors: a runtime fss::Error naming the file.

void expect_runtime_error_naming(const std::filesystem::path& path) {
  EXPECT_TRUE(test::throws_error([&] { read_png(path); }, ErrorKind::kRuntime, {path.string()}));
}

class ReadPngErrors : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const Bytes& bytes) {
    auto path = dir_ / name;
    test::write_file(path, as_string(bytes));
    return path;
  }
  test::TempDir dir_;
};

TEST_F(ReadPngErrors, MissingFile) { expect_runtime_error_naming(dir_ / "missing.png"); }

TEST_F(ReadPngErrors, Directory) {
  std::filesystem::create_directory(dir_ / "folder.png");
  expect_runtime_error_naming(dir_ / "folder.png");
}

TEST_F(ReadPngErrors, EmptyFile) { expect_runtime_error_naming(write("empty.png", {})); }

TEST_F(ReadPngErrors, TextFile) {
  const std::string text = "this is not a PNG file, just some text\n";
  expect_runtime_error_naming(write("text.png", Bytes(text.begin(), text.end())));
}

TEST_F(ReadPngErrors, SignatureOnly) {
  const Bytes valid = valid_noisy_png();
  expect_runtime_error_naming(write("signature.png", Bytes(valid.begin(), valid.begin() + 8)));
}

TEST_F(ReadPngErrors, TruncatedFile) {
  const Bytes valid = valid_noisy_png();
  ASSERT_GT(valid.size(), 4000u) << "the test image should not compress much";
  const Bytes half(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2));
  expect_runtime_error_naming(write("truncated.png", half));
}

TEST_F(ReadPngErrors, CorruptedIdatCrc) {
  std::vector<Chunk> chunks = split_chunks(valid_noisy_png());
  Chunk* idat = find_chunk(&chunks, "IDAT");
  ASSERT_NE(idat, nullptr);
  idat->crc ^= 0x00010000u;
  expect_runtime_error_naming(write("bad-crc.png", join_chunks(chunks)));
}

TEST_F(ReadPngErrors, CorruptedZlibHeader) {
  std::vector<Chunk> chunks = split_chunks(valid_noisy_png());
  Chunk* idat = find_chunk(&chunks, "IDAT");
  ASSERT_NE(idat, nullptr);
  ASSERT_GT(idat->data.size(), 3u);
  idat->data[0] = 0xff;  // CMF: compression method 15 does not exist
  idat->data[1] = 0xff;
  idat->crc = chunk_crc(*idat);  // the CRC is right: only the data is bad
  expect_runtime_error_naming(write("bad-zlib-header.png", join_chunks(chunks)));
}

TEST_F(ReadPngErrors, CorruptedDeflateBlock) {
  std::vector<Chunk> chunks = split_chunks(valid_noisy_png());
  Chunk* idat = find_chunk(&chunks, "IDAT");
  ASSERT_NE(idat, nullptr);
  ASSERT_GT(idat->data.size(), 3u);
  idat->data[2] = 0xff;  // first block header: BFINAL 1, BTYPE 3 (reserved, invalid)
  idat->crc = chunk_crc(*idat);
  expect_runtime_error_naming(write("bad-deflate.png", join_chunks(chunks)));
}

TEST_F(ReadPngErrors, ZeroWidth) {
  expect_runtime_error_naming(write("zero-width.png", png_with_declared_size(0, 4)));
}

TEST_F(ReadPngErrors, ZeroHeight) {
  expect_runtime_error_naming(write("zero-height.png", png_with_declared_size(4, 0)));
}

TEST_F(ReadPngErrors, AbsurdDimensionsAreRefusedWithoutAllocating) {
  // 10^12 pixels: an attempt to allocate them would fail with std::bad_alloc
  // (not an fss::Error) or take the machine's memory.
  expect_runtime_error_naming(write("huge.png", png_with_declared_size(1000000, 1000000)));
}

TEST_F(ReadPngErrors, SideAboveTheLimitIsRefused) {
  const auto side = static_cast<std::uint32_t>(kMaxImageSide) + 1;
  expect_runtime_error_naming(write("wide.png", png_with_declared_size(side, 1)));
  expect_runtime_error_naming(write("tall.png", png_with_declared_size(1, side)));
}

TEST(DecodePngErrors, MessageNamesTheGivenName) {
  const Bytes valid = valid_noisy_png();
  const Bytes half(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2));
  EXPECT_TRUE(test::throws_error([&] { decode(half, "memory-image-name"); }, ErrorKind::kRuntime,
                                 {"memory-image-name"}));
}

// Peak resident memory of this process so far, in bytes.
long long peak_resident_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;
}

TEST_F(ReadPngErrors, DeclaredSizeTheFileCannotHoldIsRefusedBeforeAllocating) {
  // 65536 x 65536 is within kMaxImageSide, but 4 GiB of pixels cannot come
  // out of a file of a few hundred bytes (deflate expands 1032 times at
  // most). Before the check, 4 GiB were allocated and zeroed first.
  const Bytes png = png_with_declared_size(65536, 65536);
  ASSERT_LT(png.size(), 1000u);
  const long long before = peak_resident_bytes();
  EXPECT_TRUE(test::throws_error([&] { decode(png, "declared.png"); }, ErrorKind::kRuntime,
                                 {"declared.png", "65536x65536"}));
  const long long growth = peak_resident_bytes() - before;
  EXPECT_LT(growth, 256LL << 20) << "peak memory grew by " << growth << " bytes";
}

TEST(DecodePng, ADeclaredSizeTheFileCanHoldIsRead) {
  // The bound refuses nothing real: a constant image, about as compressible
  // as a PNG gets, is read.
  const Bytes png = encode_png8(Image(4096, 1024, 1, 77.0));
  EXPECT_GT(4096.0 * 1024.0 / static_cast<double>(png.size()), 100.0) << "not compressed much";
  const Image image = decode(png);
  EXPECT_EQ(image.width, 4096);
  EXPECT_EQ(image.height, 1024);
  EXPECT_EQ(image.data.front(), 77.0);
  EXPECT_EQ(image.data.back(), 77.0);
}

}  // namespace
}  // namespace fss

namespace fss {
namespace {

TEST(PngLimit, RefusedFromTheHeaderAboveTheLimit) {
  const Image image = test::make_test_image(40, 30, 3, 1);
  const std::vector<std::uint8_t> bytes = encode_png8(image);
  const std::size_t needed = png_decode_bytes(40, 30, 3, 40 * 3);
  EXPECT_EQ(needed, 40u * 30u * 3u + 40u * 30u * 3u * sizeof(double));
  // The file's bytes are held while it is decoded: they count too.
  const std::size_t with_file = needed + bytes.size();
  EXPECT_TRUE(test::throws_error(
      [&] { decode_png(bytes.data(), bytes.size(), "small.png", with_file - 1); },
      ErrorKind::kLimit, {"small.png", "40 x 30"}));
  const Image decoded = decode_png(bytes.data(), bytes.size(), "small.png", with_file);
  EXPECT_EQ(decoded.width, 40);
}

TEST(FormatBytes, BinaryUnits) {
  EXPECT_EQ(format_bytes(512), "512 bytes");
  EXPECT_EQ(format_bytes(1024.0 * 1024.0), "1.0 MiB");
  EXPECT_EQ(format_bytes(1.5 * 1024.0 * 1024.0 * 1024.0), "1.5 GiB");
}

}  // namespace
}  // namespace fss
