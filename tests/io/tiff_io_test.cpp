// Tests of TIFF reading and float TIFF encoding (tiff_io.h), of the input
// dispatch by signature (image_io.h) and of 16-bit PNG encoding (png_io.h):
// exact round trips, every accepted layout written here with libtiff itself,
// and one-line errors for every refused or hostile file, with nothing from
// libtiff on stderr.
#include "fss/io/tiff_io.h"

#include <gtest/gtest.h>
#include <tiffio.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/image_io.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Bytes = std::vector<std::uint8_t>;

// ---------------------------------------------------------------------------
// Writing test TIFFs with libtiff.

struct TiffSpec {
  std::uint32_t width = 5;
  std::uint32_t height = 3;
  std::uint16_t samples_per_pixel = 1;
  std::uint16_t bits = 8;
  std::uint16_t format = SAMPLEFORMAT_UINT;
  std::uint16_t photometric = PHOTOMETRIC_MINISBLACK;
  std::uint16_t planar = PLANARCONFIG_CONTIG;
  std::uint16_t compression = COMPRESSION_NONE;
  std::uint32_t tile = 0;  // 0: strips
  std::uint32_t rows_per_strip = 2;
  int pages = 1;
};

// The sample (x, y, s) of the test images, exact in every sample type.
double test_sample(const TiffSpec& spec, std::uint32_t x, std::uint32_t y, int s) {
  const double base = (x * 37 + y * 101 + static_cast<std::uint32_t>(s) * 53) % 256;
  if (spec.format == SAMPLEFORMAT_IEEEFP) return base * 1.25 - 100.5;  // negatives too
  if (spec.bits == 16) return base * 255 + x;
  return base;
}

void put_sample(const TiffSpec& spec, double value, std::uint8_t* at) {
  if (spec.format == SAMPLEFORMAT_IEEEFP && spec.bits == 32) {
    const auto v = static_cast<float>(value);
    std::memcpy(at, &v, 4);
  } else if (spec.format == SAMPLEFORMAT_IEEEFP && spec.bits == 64) {
    std::memcpy(at, &value, 8);
  } else if (spec.format == SAMPLEFORMAT_IEEEFP) {  // 16-bit float: refused, any bits serve
    std::memset(at, 0, spec.bits / 8);
  } else if (spec.bits == 32) {
    const auto v = static_cast<std::uint32_t>(value);
    std::memcpy(at, &v, 4);
  } else if (spec.bits == 16) {
    const auto v = static_cast<std::uint16_t>(value);
    std::memcpy(at, &v, 2);
  } else {
    *at = static_cast<std::uint8_t>(value);
  }
}

void set_fields(TIFF* tiff, const TiffSpec& spec) {
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, spec.width);
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, spec.height);
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, spec.samples_per_pixel);
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, spec.bits);
  TIFFSetField(tiff, TIFFTAG_SAMPLEFORMAT, spec.format);
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, spec.photometric);
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, spec.planar);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, spec.compression);
  const int colour = spec.photometric == PHOTOMETRIC_RGB ? 3 : 1;
  if (spec.samples_per_pixel > colour) {
    std::vector<std::uint16_t> extra(spec.samples_per_pixel - colour, EXTRASAMPLE_UNASSALPHA);
    TIFFSetField(tiff, TIFFTAG_EXTRASAMPLES, static_cast<std::uint16_t>(extra.size()),
                 extra.data());
  }
  if (spec.photometric == PHOTOMETRIC_PALETTE) {
    std::vector<std::uint16_t> map(std::size_t{1} << spec.bits, 0);
    TIFFSetField(tiff, TIFFTAG_COLORMAP, map.data(), map.data(), map.data());
  }
  if (spec.tile > 0) {
    TIFFSetField(tiff, TIFFTAG_TILEWIDTH, spec.tile);
    TIFFSetField(tiff, TIFFTAG_TILELENGTH, spec.tile);
  } else {
    TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, spec.rows_per_strip);
  }
}

// Where a chunk (a scanline or a tile) of a test TIFF lies.
struct ChunkPlace {
  int plane;
  std::uint32_t x0, y0, width, height;
  int per_pixel;  // samples a pixel in the chunk
};

// Fills `chunk` with the test samples; zero outside the image.
void fill_chunk(const TiffSpec& spec, const ChunkPlace& at, std::vector<std::uint8_t>* chunk) {
  const std::size_t bytes = spec.bits / 8;
  std::fill(chunk->begin(), chunk->end(), 0);
  for (std::uint32_t r = 0; r < at.height && at.y0 + r < spec.height; ++r) {
    for (std::uint32_t i = 0; i < at.width && at.x0 + i < spec.width; ++i) {
      for (int k = 0; k < at.per_pixel; ++k) {
        const int s = at.per_pixel == 1 ? at.plane : k;
        put_sample(spec, test_sample(spec, at.x0 + i, at.y0 + r, s),
                   chunk->data() + ((r * at.width + i) * at.per_pixel + k) * bytes);
      }
    }
  }
}

// Writes the chunks of one page: scanlines or tiles, one plane at a time
// when samples are separate.
void write_page(TIFF* tiff, const TiffSpec& spec) {
  const bool separate = spec.planar == PLANARCONFIG_SEPARATE;
  const int planes = separate ? spec.samples_per_pixel : 1;
  const int per_pixel = separate ? 1 : spec.samples_per_pixel;
  const std::uint32_t chunk_w = spec.tile > 0 ? spec.tile : spec.width;
  const std::uint32_t chunk_h = spec.tile > 0 ? spec.tile : 1;
  std::vector<std::uint8_t> chunk(static_cast<std::size_t>(chunk_w) * chunk_h * per_pixel *
                                  (spec.bits / 8));
  for (int plane = 0; plane < planes; ++plane) {
    for (std::uint32_t y0 = 0; y0 < spec.height; y0 += chunk_h) {
      for (std::uint32_t x0 = 0; x0 < spec.width; x0 += chunk_w) {
        fill_chunk(spec, {plane, x0, y0, chunk_w, chunk_h, per_pixel}, &chunk);
        const auto p = static_cast<std::uint16_t>(plane);
        const bool ok = spec.tile > 0 ? TIFFWriteTile(tiff, chunk.data(), x0, y0, 0, p) >= 0
                                      : TIFFWriteScanline(tiff, chunk.data(), y0, p) == 1;
        ASSERT_TRUE(ok);
      }
    }
  }
}

Bytes craft_tiff(const TiffSpec& spec) {
  test::TempDir dir;
  const std::string path = (dir / "crafted.tif").string();
  TIFF* tiff = TIFFOpen(path.c_str(), "w");
  EXPECT_NE(tiff, nullptr);
  if (tiff == nullptr) return {};
  for (int page = 0; page < spec.pages; ++page) {
    set_fields(tiff, spec);
    write_page(tiff, spec);
    TIFFWriteDirectory(tiff);
  }
  TIFFClose(tiff);
  const std::string text = test::read_file(path);
  return {text.begin(), text.end()};
}

Image decode(const Bytes& bytes, std::size_t max_bytes = 0) {
  return decode_tiff(bytes.data(), bytes.size(), "test.tif", max_bytes);
}

// The value fssim reads from a sample: 8-bit s, 16-bit s / 257, float as is.
double expected_value(const TiffSpec& spec, std::uint32_t x, std::uint32_t y, int s) {
  const double v = test_sample(spec, x, y, s);
  if (spec.format == SAMPLEFORMAT_IEEEFP) return static_cast<float>(v);
  return spec.bits == 16 ? v / 257.0 : v;
}

void expect_values(const TiffSpec& spec, const Image& image) {
  const int channels = spec.photometric == PHOTOMETRIC_RGB ? 3 : 1;
  ASSERT_EQ(image.width, static_cast<int>(spec.width));
  ASSERT_EQ(image.height, static_cast<int>(spec.height));
  ASSERT_EQ(image.channels, channels);
  for (int c = 0; c < channels; ++c) {
    for (std::uint32_t y = 0; y < spec.height; ++y) {
      for (std::uint32_t x = 0; x < spec.width; ++x) {
        ASSERT_EQ(image.at(c, static_cast<int>(y), static_cast<int>(x)),
                  expected_value(spec, x, y, c))
            << "c " << c << " y " << y << " x " << x;
      }
    }
  }
}

// Runs f with stderr captured: libtiff must print nothing.
template <typename F>
void expect_silent(F&& f) {
  ::testing::internal::CaptureStderr();
  f();
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

// decode(bytes) must throw one runtime error naming the file and containing
// each of `parts`, on one line, with nothing on stderr.
::testing::AssertionResult refused(const Bytes& bytes,
                                   std::initializer_list<std::string_view> parts = {},
                                   ErrorKind kind = ErrorKind::kRuntime,
                                   std::size_t max_bytes = 0) {
  ::testing::internal::CaptureStderr();
  const std::optional<Error> error = test::error_of([&] { decode(bytes, max_bytes); });
  const std::string err = ::testing::internal::GetCapturedStderr();
  if (!err.empty()) return ::testing::AssertionFailure() << "stderr: " << err;
  if (!error) return ::testing::AssertionFailure() << "accepted";
  const std::string message = error->what();
  if (error->kind() != kind) return ::testing::AssertionFailure() << "kind of: " << message;
  if (message.find('\n') != std::string::npos) {
    return ::testing::AssertionFailure() << "not one line: " << message;
  }
  if (message.find("test.tif") == std::string::npos) {
    return ::testing::AssertionFailure() << "file not named: " << message;
  }
  for (const std::string_view part : parts) {
    if (message.find(part) == std::string::npos) {
      return ::testing::AssertionFailure() << "'" << part << "' is not in: " << message;
    }
  }
  return ::testing::AssertionSuccess() << message;
}

// ---------------------------------------------------------------------------
// Float TIFFs: exact round trips.

Image values_image(int width, int height, int channels) {
  Image image(width, height, channels);
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    // negatives, values above 255, fractions and tiny magnitudes
    image.data[i] = (static_cast<double>(i % 97) - 40.0) * 3.3 + 1e-7 * static_cast<double>(i);
  }
  return image;
}

TEST(FloatTiff, RoundTripGivesTheNearestFloatOfEveryValueBitForBit) {
  for (const int channels : {1, 3}) {
    const Image image = values_image(37, 300, channels);  // several strips
    const Bytes bytes = encode_tiff_float(image);
    const Image back = decode(bytes);
    ASSERT_EQ(back.width, 37);
    ASSERT_EQ(back.height, 300);
    ASSERT_EQ(back.channels, channels);
    for (std::size_t i = 0; i < image.data.size(); ++i) {
      const auto expected = static_cast<float>(image.data[i]);
      const auto got = static_cast<float>(back.data[i]);
      ASSERT_EQ(std::bit_cast<std::uint32_t>(expected), std::bit_cast<std::uint32_t>(got)) << i;
      ASSERT_EQ(back.data[i], static_cast<double>(expected)) << i;  // a float, widened exactly
    }
  }
}

TEST(FloatTiff, FileIsA32BitFloatTiffWithTheImageChannels) {
  for (const int channels : {1, 3}) {
    const Bytes bytes = encode_tiff_float(values_image(7, 4, channels));
    test::TempDir dir;
    test::write_file(dir / "f.tif", std::string(bytes.begin(), bytes.end()));
    TIFF* tiff = TIFFOpen((dir / "f.tif").c_str(), "r");
    ASSERT_NE(tiff, nullptr);
    std::uint16_t bits = 0, format = 0, spp = 0, planar = 0, photometric = 0;
    TIFFGetField(tiff, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetField(tiff, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetField(tiff, TIFFTAG_SAMPLESPERPIXEL, &spp);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_PLANARCONFIG, &planar);
    TIFFGetField(tiff, TIFFTAG_PHOTOMETRIC, &photometric);
    EXPECT_EQ(bits, 32);
    EXPECT_EQ(format, SAMPLEFORMAT_IEEEFP);
    EXPECT_EQ(spp, channels);
    EXPECT_EQ(planar, PLANARCONFIG_CONTIG);
    EXPECT_EQ(photometric, channels == 1 ? PHOTOMETRIC_MINISBLACK : PHOTOMETRIC_RGB);
    EXPECT_TRUE(TIFFLastDirectory(tiff));
    TIFFClose(tiff);
  }
}

TEST(FloatTiff, SameValuesGiveSameBytesAndRowsEqualTheImage) {
  const Image image = values_image(20, 9, 3);
  const Bytes whole = encode_tiff_float(image);
  EXPECT_EQ(encode_tiff_float(image), whole);
  const Bytes by_rows = encode_tiff_float(20, 9, 3, [&](int c, int y, double* row) {
    for (int x = 0; x < 20; ++x) row[x] = image.at(c, y, x);
  });
  EXPECT_EQ(by_rows, whole);
}

TEST(FloatTiff, NonFiniteValuesAreWrittenButRefusedOnReading) {
  Image image(3, 2, 1, 1.0);
  image.at(0, 1, 2) = std::numeric_limits<double>::infinity();
  const Bytes bytes = encode_tiff_float(image);
  EXPECT_TRUE(refused(bytes, {"non-finite", "row 1, column 2"}));
  image.at(0, 1, 2) = std::nan("");
  EXPECT_TRUE(refused(encode_tiff_float(image), {"non-finite"}));
}

TEST(FloatTiff, EncodingRefusesWhatATiffCannotHold) {
  EXPECT_TRUE(test::throws_error([] { encode_tiff_float(Image(2, 2, 2)); }, ErrorKind::kUsage,
                                 {"1 or 3 channels"}));
  EXPECT_TRUE(test::throws_error([] { encode_tiff_float(Image(0, 3, 1)); }, ErrorKind::kUsage,
                                 {"pixels a side"}));
}

// ---------------------------------------------------------------------------
// Reading every accepted layout.

TEST(TiffReading, EverySampleTypeColourAndLayoutGivesTheExpectedValues) {
  const std::vector<std::pair<std::uint16_t, std::uint16_t>> types = {
      {8, SAMPLEFORMAT_UINT}, {16, SAMPLEFORMAT_UINT}, {32, SAMPLEFORMAT_IEEEFP}};
  const std::vector<std::pair<std::uint16_t, std::uint16_t>> colours = {
      {PHOTOMETRIC_MINISBLACK, 1},
      {PHOTOMETRIC_MINISBLACK, 2},  // gray, gray + alpha
      {PHOTOMETRIC_RGB, 3},
      {PHOTOMETRIC_RGB, 4}};  // RGB, RGBA
  for (const auto& [bits, format] : types) {
    for (const auto& [photometric, spp] : colours) {
      for (const std::uint16_t planar : {PLANARCONFIG_CONTIG, PLANARCONFIG_SEPARATE}) {
        for (const std::uint32_t tile : {0U, 16U}) {
          TiffSpec spec;
          spec.width = 21;  // tiles pass the right and bottom edges
          spec.height = 18;
          spec.bits = bits;
          spec.format = format;
          spec.photometric = photometric;
          spec.samples_per_pixel = spp;
          spec.planar = planar;
          spec.tile = tile;
          SCOPED_TRACE(testing::Message()
                       << bits << "-bit format " << format << " photometric " << photometric
                       << " spp " << spp << " planar " << planar << " tile " << tile);
          const Bytes bytes = craft_tiff(spec);
          expect_silent([&] { expect_values(spec, decode(bytes)); });
        }
      }
    }
  }
}

TEST(TiffReading, EveryAcceptedCompressionGivesTheSameValues) {
  for (const std::uint16_t compression :
       {COMPRESSION_NONE, COMPRESSION_PACKBITS, COMPRESSION_LZW, COMPRESSION_ADOBE_DEFLATE}) {
    TiffSpec spec;
    spec.width = 40;
    spec.height = 11;
    spec.bits = 16;
    spec.photometric = PHOTOMETRIC_RGB;
    spec.samples_per_pixel = 3;
    spec.compression = compression;
    spec.rows_per_strip = 4;
    SCOPED_TRACE(compression);
    expect_values(spec, decode(craft_tiff(spec)));
  }
}

TEST(TiffReading, SixteenBitSamplesAreOnThePngScale) {
  TiffSpec spec;
  spec.bits = 16;
  const Image image = decode(craft_tiff(spec));
  // the 16-bit PNG convention of image.h: sample / 257, so 257 g reads as g
  EXPECT_EQ(image.at(0, 0, 0), test_sample(spec, 0, 0, 0) / 257.0);
  EXPECT_EQ(png16_sample(image.at(0, 2, 4)), test_sample(spec, 4, 2, 0));
}

// ---------------------------------------------------------------------------
// Refusals.

TEST(TiffReading, RefusesSampleTypesItDoesNotRead) {
  struct Case {
    std::uint16_t bits, format;
    const char* says;
  };
  for (const Case& c : {Case{16, SAMPLEFORMAT_INT, "16-bit signed integer"},
                        Case{8, SAMPLEFORMAT_INT, "8-bit signed integer"},
                        Case{32, SAMPLEFORMAT_UINT, "32-bit unsigned integer"},
                        Case{64, SAMPLEFORMAT_IEEEFP, "64-bit float"},
                        Case{16, SAMPLEFORMAT_IEEEFP, "16-bit float"}}) {
    TiffSpec spec;
    spec.bits = c.bits;
    spec.format = c.format;
    EXPECT_TRUE(refused(craft_tiff(spec), {c.says, "fssim reads"})) << c.says;
  }
}

TEST(TiffReading, RefusesColoursItDoesNotRead) {
  TiffSpec palette;
  palette.photometric = PHOTOMETRIC_PALETTE;
  EXPECT_TRUE(refused(craft_tiff(palette), {"palette", "gray (min-is-black) and RGB"}));
  TiffSpec white;
  white.photometric = PHOTOMETRIC_MINISWHITE;
  EXPECT_TRUE(refused(craft_tiff(white), {"min-is-white"}));
  TiffSpec cmyk;
  cmyk.photometric = PHOTOMETRIC_SEPARATED;
  cmyk.samples_per_pixel = 4;
  EXPECT_TRUE(refused(craft_tiff(cmyk), {"CMYK"}));
}

TEST(TiffReading, RefusesSeveralPages) {
  TiffSpec spec;
  spec.pages = 2;
  EXPECT_TRUE(refused(craft_tiff(spec), {"several images", "single-image"}));
}

TEST(TiffReading, RefusesOtherCompressions) {
  int tried = 0;
  for (const std::uint16_t compression : {COMPRESSION_ZSTD, COMPRESSION_LZMA, COMPRESSION_JPEG}) {
    if (!TIFFIsCODECConfigured(compression)) continue;
    TiffSpec spec;
    spec.width = 16;
    spec.height = 16;
    spec.rows_per_strip = 16;
    spec.compression = compression;
    EXPECT_TRUE(
        refused(craft_tiff(spec), {"compression", "uncompressed, PackBits, LZW and Deflate"}))
        << compression;
    ++tried;
  }
  if (tried == 0) GTEST_SKIP() << "this libtiff writes no other compression";
}

TEST(TiffReading, RefusesTruncatedFiles) {
  TiffSpec spec;
  spec.width = 64;
  spec.height = 64;
  const Bytes whole = craft_tiff(spec);
  for (const std::size_t size :
       {std::size_t{4}, std::size_t{8}, whole.size() / 2, whole.size() - 20}) {
    const Bytes cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size));
    EXPECT_TRUE(refused(cut)) << size;
  }
}

TEST(TiffReading, RefusesWhatIsNotATiff) {
  const Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_TRUE(refused(png, {"not a TIFF file"}));
  EXPECT_TRUE(refused(Bytes{}, {"not a TIFF file"}));
}

// A hand-made little-endian TIFF: one IFD of 8-bit gray, uncompressed, one
// strip of `strip_bytes` declared bytes, declaring width x height pixels.
Bytes header_only_tiff(std::uint32_t width, std::uint32_t height, std::uint32_t strip_bytes) {
  Bytes out = {'I', 'I', 42, 0, 8, 0, 0, 0};
  const auto put16 = [&](std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
  };
  const auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  struct Entry {
    std::uint16_t tag, type;
    std::uint32_t value;
  };
  const std::uint32_t data_offset = 8 + 2 + 9 * 12 + 4;
  const Entry entries[] = {{256, 4, width}, {257, 4, height}, {258, 3, 8},
                           {259, 3, 1},     {262, 3, 1},      {273, 4, data_offset},
                           {277, 3, 1},     {278, 4, height}, {279, 4, strip_bytes}};
  put16(9);
  for (const Entry& e : entries) {
    put16(e.tag);
    put16(e.type);
    put32(1);
    if (e.type == 3) {
      put16(static_cast<std::uint16_t>(e.value));
      put16(0);
    } else {
      put32(e.value);
    }
  }
  put32(0);                        // no next IFD
  out.resize(out.size() + 64, 7);  // a little pixel data
  return out;
}

TEST(TiffReading, HugeDimensionsAreRefusedFromTheHeaderBeforeDecoding) {
  const Bytes fine = header_only_tiff(8, 8, 64);
  const Image image = decode(fine);
  EXPECT_EQ(image.at(0, 7, 7), 7.0);
  EXPECT_TRUE(refused(header_only_tiff(65536, 65536, 64), {"65536x65536", "can hold"}));
  EXPECT_TRUE(refused(header_only_tiff(100000, 2, 64), {"100000x2", "at most 65536"}));
  // a file that holds its pixels, over the memory limit: kLimit, from the header
  EXPECT_TRUE(refused(header_only_tiff(8, 8, 64), {"memory limit"}, ErrorKind::kLimit, 100));
}

// The fuzzer's seed corpus (tests/fuzz/make_corpus.py writes it by hand,
// without libtiff): what its names say is accepted reads with the values the
// script wrote, the rest is refused.
TEST(TiffReading, TheFuzzSeedsAreReadOrRefusedAsTheirNamesSay) {
  const auto level = [](int x, int y, int s, int top) {
    const int whole = (x * 37 + y * 19 + s * 71) % 251 * top / 250;  // as the script's //
    return static_cast<double>(whole);
  };
  const auto seed = [](const std::string& name) {
    const std::string text = test::read_file(test::source_path("tests/fuzz/corpus/tiff/" + name));
    return Bytes(text.begin(), text.end());
  };
  struct Accepted {
    const char* name;
    int width, height, channels, top;  // top: 0 for float samples
  };
  for (const Accepted& a :
       {Accepted{"gray8.tif", 16, 12, 1, 255}, Accepted{"gray8-big-endian.tif", 9, 7, 1, 255},
        Accepted{"gray16-deflate.tif", 20, 10, 1, 65535},
        Accepted{"gray16-big-endian-packbits.tif", 18, 6, 1, 65535},
        Accepted{"graya8.tif", 10, 8, 1, 255}, Accepted{"rgb8-tiled.tif", 20, 18, 3, 255},
        Accepted{"rgba16-separate.tif", 7, 5, 3, 65535}, Accepted{"rgb-float32.tif", 8, 6, 3, 0},
        Accepted{"gray-float32-tiled-separate.tif", 17, 3, 1, 0},
        Accepted{"gray8-1x1.tif", 1, 1, 1, 255}, Accepted{"bigtiff-gray8.tif", 12, 5, 1, 255}}) {
    SCOPED_TRACE(a.name);
    const Image image = decode(seed(a.name));
    ASSERT_EQ(image.width, a.width);
    ASSERT_EQ(image.height, a.height);
    ASSERT_EQ(image.channels, a.channels);
    const int x = a.width - 1, y = a.height - 1, c = a.channels - 1;
    const double want = a.top == 0     ? x * 3.25 - y * 1.5 + c * 40.0 - 12.0
                        : a.top == 255 ? level(x, y, c, 255)
                                       : level(x, y, c, 65535) / 257.0;
    EXPECT_EQ(image.at(c, y, x), want);
  }
  for (const char* name : {"two-pages.tif", "palette8.tif", "int16.tif", "float64.tif"}) {
    EXPECT_TRUE(refused(seed(name))) << name;
  }
}

// ---------------------------------------------------------------------------
// Dispatch by signature.

TEST(ImageDispatch, ReadsTiffAndPngByTheirBytesWhateverTheirName) {
  test::TempDir dir;
  const Image image = values_image(6, 4, 3);
  const Bytes tiff = encode_tiff_float(image);
  const Bytes png = encode_png8(test::make_test_image(6, 4, 1));
  test::write_file(dir / "really_a_tiff.png", std::string(tiff.begin(), tiff.end()));
  test::write_file(dir / "really_a_png.tif", std::string(png.begin(), png.end()));
  ImageFileInfo info;
  const Image from_tiff = read_image(dir / "really_a_tiff.png", 0, &info);
  EXPECT_EQ(info.format, ImageFileFormat::kTiff);
  EXPECT_EQ(info.bits_per_sample, 32);
  EXPECT_TRUE(info.floating);
  EXPECT_EQ(from_tiff.data, decode(tiff).data);
  const Image from_png = read_image(dir / "really_a_png.tif", 0, &info);
  EXPECT_EQ(info.format, ImageFileFormat::kPng);
  EXPECT_EQ(info.bits_per_sample, 8);
  EXPECT_FALSE(info.floating);
  EXPECT_EQ(from_png.data, decode_png(png.data(), png.size(), "x.png").data);
  EXPECT_EQ(read_tiff(dir / "really_a_tiff.png").data, from_tiff.data);
  const Bytes png16 = encode_png(image, PngDepth::k16);
  decode_image(png16.data(), png16.size(), "deep.png", 0, &info);
  EXPECT_EQ(info.format, ImageFileFormat::kPng);
  EXPECT_EQ(info.bits_per_sample, 16);
}

TEST(ImageDispatch, RefusesOtherFilesInOneLine) {
  test::TempDir dir;
  test::write_file(dir / "text.tif", "neither a PNG nor a TIFF\n");
  EXPECT_TRUE(test::throws_error([&] { read_image(dir / "text.tif"); }, ErrorKind::kRuntime,
                                 {"text.tif", "not a PNG or TIFF file"}));
  test::write_file(dir / "empty.tif", "");
  EXPECT_TRUE(test::throws_error([&] { read_image(dir / "empty.tif"); }, ErrorKind::kRuntime,
                                 {"empty.tif", "is empty"}));
  EXPECT_TRUE(
      test::throws_error([&] { read_image(dir.path()); }, ErrorKind::kRuntime, {"is a directory"}));
}

TEST(ImageDispatch, AnEightBitTiffReadsAsTheSamePng) {
  const Image image = test::make_test_image(30, 7, 3);
  const Bytes png = encode_png8(image);
  const Image from_png = decode_png(png.data(), png.size(), "x.png");
  TiffSpec spec;  // the same samples through libtiff
  test::TempDir dir;
  TIFF* tiff = TIFFOpen((dir / "x.tif").c_str(), "w");
  ASSERT_NE(tiff, nullptr);
  spec.width = 30;
  spec.height = 7;
  spec.photometric = PHOTOMETRIC_RGB;
  spec.samples_per_pixel = 3;
  spec.compression = COMPRESSION_LZW;
  set_fields(tiff, spec);
  std::vector<std::uint8_t> row(30 * 3);
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 30; ++x) {
      for (int c = 0; c < 3; ++c) row[x * 3 + c] = png8_sample(image.at(c, y, x));
    }
    ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), static_cast<std::uint32_t>(y), 0), 1);
  }
  TIFFClose(tiff);
  EXPECT_EQ(read_image(dir / "x.tif").data, from_png.data);
}

// ---------------------------------------------------------------------------
// 16-bit PNG encoding.

TEST(Png16, EverySixteenBitSampleSurvivesReadingAndEncoding) {
  for (int s = 0; s <= 65535; ++s) ASSERT_EQ(png16_sample(s / 257.0), s) << s;
  for (int g = 0; g <= 255; ++g) EXPECT_EQ(png16_sample(g), 257 * g);
  EXPECT_EQ(png16_sample(-3.0), 0);
  EXPECT_EQ(png16_sample(300.0), 65535);
  EXPECT_EQ(png16_sample(std::nan("")), 0);
  EXPECT_EQ(png16_sample(0.5 / 257.0), 1);  // halves away from zero
  EXPECT_EQ(png16_sample(0.49 / 257.0), 0);
}

TEST(Png16, ASixteenBitPngReadsBackAsItsSamplesOver257) {
  Image image = values_image(11, 5, 3);
  const Bytes png = encode_png(image, PngDepth::k16);
  ASSERT_GT(png.size(), 25U);
  EXPECT_EQ(png[24], 16);  // IHDR bit depth
  const Image back = decode_png(png.data(), png.size(), "x.png");
  ASSERT_EQ(back.data.size(), image.data.size());
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    ASSERT_EQ(back.data[i], png16_sample(image.data[i]) / 257.0) << i;
  }
}

TEST(Png16, EightBitsGiveTheBytesOfEncodePng8) {
  const Image image = values_image(9, 4, 1);
  EXPECT_EQ(encode_png(image, PngDepth::k8), encode_png8(image));
  EXPECT_EQ(to_string(PngDepth::k16), "16");
  EXPECT_EQ(png_depth_from_string("8"), PngDepth::k8);
  EXPECT_EQ(png_depth_from_string("12"), std::nullopt);
}

}  // namespace
}  // namespace fss
