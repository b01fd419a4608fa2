// Robustness of the fssim binary (issue 6): every bad input file, code file
// or option ends in exactly one clear line on stderr and exit status 2 (usage)
// or 1 (runtime), never in a crash, an abort, a sanitizer report or a silent
// NaN; and a failed run leaves the output directory exactly as it was, a
// previous run's outputs included. Valid but unusual PNGs (interlaced, 16-bit,
// palette, gray+alpha, RGBA) run.
//
// Some cases repeat an error test of cli_test.cpp on purpose: here each one
// also checks that an output directory holding a previous run's files is
// left byte for byte as it was.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <new>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/outputs.h"
#include "fss/io/png_io.h"
#include "nlohmann/json.hpp"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using Bytes = std::vector<std::uint8_t>;

// ---------------------------------------------------------------------------
// Shell quoting, directory snapshots, stderr checks.

// `text` as one single-quoted shell word (any byte but NUL is fine in it).
std::string quote(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}
std::string quote(const fs::path& path) { return quote(path.string()); }

using test::lines_of;

// Every entry under `dir`, recursively: relative path -> "dir" or the bytes
// of the file. Two equal snapshots mean nothing was added, removed or changed.
using Snapshot = std::map<std::string, std::string>;
Snapshot snapshot(const fs::path& dir) {
  Snapshot entries;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = fs::relative(entry.path(), dir).string();
    entries[name] = entry.is_directory() ? "dir" : "file: " + test::read_file(entry.path());
  }
  return entries;
}

std::vector<std::string> names_of(const Snapshot& snapshot) {
  std::vector<std::string> names;
  for (const auto& [name, content] : snapshot) names.push_back(name);
  return names;
}

// A failure as issue 6 wants it: the exit status, one line on stderr that
// starts with "fssim: error:" and names every culprit, nothing on stdout, and
// no trace of a crash or of a sanitizer.
void expect_clean_failure(const CommandResult& r, int exit_code,
                          const std::vector<std::string>& culprits) {
  EXPECT_EQ(r.exit_code, exit_code) << "stderr:\n" << r.err;
  const std::vector<std::string> lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << "stderr:\n" << r.err;
  EXPECT_THAT(lines[0], StartsWith("fssim: error: "));
  EXPECT_EQ(r.err.back(), '\n');
  for (const std::string& culprit : culprits) EXPECT_THAT(lines[0], HasSubstr(culprit));
  for (const char* crash : {"terminate", "Aborted", "Sanitizer", "runtime error", "Segmentation",
                            "core dumped", "what():"}) {
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr(crash)));
  }
  EXPECT_EQ(r.out, "");
}

// ---------------------------------------------------------------------------
// Writing PNGs of every kind with libpng.

using test::PngSpec;

Bytes encode(const PngSpec& spec) { return test::craft_png(spec); }

// The test picture: edges, ramps and texture, in [0, 255], different per channel.
int sample(int c, int y, int x) {
  return (3 * x + 5 * y + 70 * c + ((x / 16 + y / 8) % 2) * 60 + (x * y) % 7) % 256;
}

constexpr int kWidth = 512;  // wide enough for L = 52 (9B + 1 = 469)
constexpr int kHeight = 64;

// A kWidth x kHeight PNG of `sample` in the given format. Alpha, where there
// is one, varies so that dropping it is visible; 16-bit samples carry low
// bits that survive the division by 257.
PngSpec picture(int color_type, int bit_depth, bool interlaced = false) {
  PngSpec spec;
  spec.width = kWidth;
  spec.height = kHeight;
  spec.color_type = color_type;
  spec.bit_depth = bit_depth;
  spec.interlaced = interlaced;
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < 256; ++i) {
      spec.palette.push_back({static_cast<png_byte>(i), static_cast<png_byte>(255 - i),
                              static_cast<png_byte>((i * 3) % 256)});
    }
  }
  const int colours =
      (color_type & PNG_COLOR_MASK_COLOR) && color_type != PNG_COLOR_TYPE_PALETTE ? 3 : 1;
  const bool alpha = (color_type & PNG_COLOR_MASK_ALPHA) != 0;
  for (int y = 0; y < kHeight; ++y) {
    Bytes row;
    auto put = [&](int value) {
      if (bit_depth == 16) {
        const int wide = value * 257 + (y % 3 == 0 ? 100 : 0);  // +100: rounds back to value
        row.push_back(static_cast<std::uint8_t>(std::min(wide, 65535) >> 8));
        row.push_back(static_cast<std::uint8_t>(std::min(wide, 65535) & 0xff));
      } else {
        row.push_back(static_cast<std::uint8_t>(value));
      }
    };
    for (int x = 0; x < kWidth; ++x) {
      for (int c = 0; c < colours; ++c) put(sample(c, y, x));
      if (alpha) put((x * 37 + y * 11) % 256);
    }
    spec.rows.push_back(row);
  }
  return spec;
}

// The value fssim must read at (c, y, x) from `picture(color_type, ...)`.
double expected_value(int color_type, int bit_depth, int c, int y, int x) {
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    const int index = sample(0, y, x);
    return c == 0 ? index : c == 1 ? 255 - index : (index * 3) % 256;
  }
  const int value = sample(c, y, x);
  if (bit_depth == 16) {
    const int wide = std::min(value * 257 + (y % 3 == 0 ? 100 : 0), 65535);
    return wide / 257.0;
  }
  return value;
}

// Chunk surgery.
std::uint32_t read_be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

void write_be32(std::uint8_t* p, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(value >> (24 - 8 * i));
}

// Offset of the length field of the first chunk of type `type`.
std::size_t chunk_offset(const Bytes& png, const char* type) {
  for (std::size_t pos = 8; pos + 12 <= png.size(); pos += 12 + read_be32(&png[pos])) {
    if (std::equal(type, type + 4, png.begin() + static_cast<std::ptrdiff_t>(pos + 4))) return pos;
  }
  ADD_FAILURE() << "no " << type << " chunk";
  return 0;
}

// Recomputes the CRC of the chunk at `pos` after its data was edited.
void fix_crc(Bytes* png, std::size_t pos) {
  const std::uint32_t length = read_be32(&(*png)[pos]);
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), &(*png)[pos + 4], length + 4);
  write_be32(&(*png)[pos + 8 + length], static_cast<std::uint32_t>(crc));
}

// A valid PNG whose IHDR declares another size, with a correct CRC.
Bytes with_declared_size(Bytes png, std::uint32_t width, std::uint32_t height) {
  const std::size_t ihdr = chunk_offset(png, "IHDR");
  write_be32(&png[ihdr + 8], width);
  write_be32(&png[ihdr + 12], height);
  fix_crc(&png, ihdr);
  return png;
}

std::string as_string(const Bytes& bytes) { return {bytes.begin(), bytes.end()}; }

// ---------------------------------------------------------------------------
// The fixture: an input directory and an output directory that already holds
// a previous run's files, which every failed run must leave as they are.

class Robustness : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directory(in_);
    fs::create_directory(out_);
    test::write_file(out_ / "observed.png", "previous observed.png \x89PNG\r\n\x1a\n\x01\x02");
    test::write_file(out_ / "report.json", "{\"previous\": true}\n");
    test::write_file(out_ / "notes.txt", "not an output of fssim\n");
    good_input_ = in_ / "good.png";
    test::write_file(good_input_, as_string(encode(picture(PNG_COLOR_TYPE_GRAY, 8))));
  }

  fs::path input(const std::string& name, const std::string& bytes) {
    const fs::path path = in_ / name;
    test::write_file(path, bytes);
    return path;
  }
  fs::path input(const std::string& name, const Bytes& bytes) {
    return input(name, as_string(bytes));
  }

  // Runs fssim with `arguments` and --outdir `outdir`; expects a clean failure
  // naming the culprits and the whole test directory unchanged.
  void expect_failure(const std::string& arguments, int exit_code,
                      const std::vector<std::string>& culprits,
                      const std::string& outdir_argument = "") {
    const std::string outdir = outdir_argument.empty() ? quote(out_) : outdir_argument;
    const Snapshot before = snapshot(dir_.path());
    // --outdir first, so that an option missing its value can be the last word.
    const CommandResult r = test::run_fssim("--outdir " + outdir + " " + arguments);
    expect_clean_failure(r, exit_code, culprits);
    const Snapshot after = snapshot(dir_.path());
    EXPECT_EQ(names_of(after), names_of(before)) << "files were added or removed";
    EXPECT_TRUE(after == before) << "a file changed";
  }

  // --input <the good 512 x 64 image> followed by `rest`.
  std::string with_good_input(const std::string& rest) {
    return "--input " + quote(good_input_) + " " + rest;
  }

  fs::path code_file(const std::string& name, const std::string& text) { return input(name, text); }

  test::TempDir dir_;
  fs::path in_ = dir_ / "in";
  fs::path out_ = dir_ / "out";
  fs::path good_input_;
};

// ---------------------------------------------------------------------------
// Input files.

TEST_F(Robustness, InputMissing) {
  const fs::path missing = in_ / "missing.png";
  expect_failure("--input " + quote(missing), 1, {missing.string(), "No such file"});
}

TEST_F(Robustness, InputIsADirectory) {
  const fs::path folder = in_ / "folder.png";
  fs::create_directory(folder);
  expect_failure("--input " + quote(folder), 1, {folder.string(), "directory"});
}

TEST_F(Robustness, InputEmpty) {
  const fs::path empty = input("empty.png", "");
  expect_failure("--input " + quote(empty), 1, {empty.string(), "empty"});
}

TEST_F(Robustness, InputNotAPng) {
  const fs::path text = input("text.png", "GIF89a, or rather some text\n");
  expect_failure("--input " + quote(text), 1, {text.string(), "not a PNG"});
}

TEST_F(Robustness, InputEndlessStreamIsRefusedAtTheSignature) {
  // Read whole, /dev/zero would take all memory; its first 8 bytes suffice.
  expect_failure("--input /dev/zero", 1, {"/dev/zero", "not a PNG"});
}

TEST_F(Robustness, InputTruncated) {
  // Cut in the middle of the image data.
  const Bytes full = encode(picture(PNG_COLOR_TYPE_RGB, 8));
  const std::size_t idat = chunk_offset(full, "IDAT");
  const std::size_t cut_at = idat + 8 + read_be32(&full[idat]) / 2;
  const fs::path cut =
      input("cut.png", Bytes(full.begin(), full.begin() + static_cast<long>(cut_at)));
  expect_failure("--input " + quote(cut), 1, {cut.string(), "truncated"});
}

TEST_F(Robustness, InputWithACorruptedCrc) {
  Bytes png = encode(picture(PNG_COLOR_TYPE_GRAY, 8));
  const std::size_t idat = chunk_offset(png, "IDAT");
  png[idat + 8 + read_be32(&png[idat]) + 1] ^= 0x40;  // one bit of the IDAT CRC
  const fs::path bad = input("bad-crc.png", png);
  expect_failure("--input " + quote(bad), 1, {bad.string(), "CRC"});
}

TEST_F(Robustness, InputWithZeroWidth) {
  const fs::path zero =
      input("zero-width.png", with_declared_size(encode(picture(PNG_COLOR_TYPE_GRAY, 8)), 0, 64));
  expect_failure("--input " + quote(zero), 1, {zero.string()});
}

TEST_F(Robustness, InputWithAbsurdDimensions) {
  const Bytes png = encode(picture(PNG_COLOR_TYPE_GRAY, 8));
  // Above libpng's limit (kMaxImageSide) ...
  const fs::path huge = input("huge.png", with_declared_size(png, 1000000, 1000000));
  expect_failure("--input " + quote(huge), 1, {huge.string()});
  // ... and within it but far more than the file holds (4 GiB of pixels).
  const fs::path big = input("big.png", with_declared_size(png, 65536, 65536));
  expect_failure("--input " + quote(big), 1, {big.string(), "65536x65536"});
}

TEST_F(Robustness, OnePixelImageIsTooNarrow) {
  PngSpec spec;
  spec.width = 1;
  spec.height = 1;
  spec.rows = {{128}};
  const fs::path tiny = input("1x1.png", encode(spec));
  expect_failure("--input " + quote(tiny), 2, {"width"});
}

// Valid PNGs of every other kind run, and fssim reads the right values:
// groundtruth.png is input columns 78 .. 433 (B = 52), rounded.
struct FormatCase {
  const char* name;
  int color_type;
  int bit_depth;
  bool interlaced;
  int channels;  // of the outputs
};

void PrintTo(const FormatCase& c, std::ostream* os) { *os << c.name; }

class RobustnessFormats : public Robustness, public ::testing::WithParamInterface<FormatCase> {};

TEST_P(RobustnessFormats, RunsAndReadsTheRightValues) {
  const FormatCase& c = GetParam();
  const fs::path path =
      input(std::string(c.name) + ".png", encode(picture(c.color_type, c.bit_depth, c.interlaced)));
  const CommandResult r = test::run_fssim("--input " + quote(path) + " --outdir " + quote(out_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const Image groundtruth = read_png(out_ / "groundtruth.png");
  ASSERT_EQ(groundtruth.width, kWidth - 3 * 52);
  ASSERT_EQ(groundtruth.height, kHeight);
  ASSERT_EQ(groundtruth.channels, c.channels);
  int wrong = 0;
  for (int ch = 0; ch < c.channels; ++ch) {
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < groundtruth.width; ++x) {
        const double want = std::round(expected_value(c.color_type, c.bit_depth, ch, y, x + 78));
        if (groundtruth.at(ch, y, x) != want && ++wrong <= 5) {
          ADD_FAILURE() << "channel " << ch << " row " << y << " column " << x << ": "
                        << groundtruth.at(ch, y, x) << ", expected " << want;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  // The previous run's files are replaced, the unrelated one kept.
  EXPECT_EQ(test::read_file(out_ / "notes.txt"), "not an output of fssim\n");
  EXPECT_NE(test::read_file(out_ / "report.json"), "{\"previous\": true}\n");
}

INSTANTIATE_TEST_SUITE_P(
    Inputs, RobustnessFormats,
    ::testing::Values(FormatCase{"Interlaced", PNG_COLOR_TYPE_RGB, 8, true, 3},
                      FormatCase{"SixteenBitGray", PNG_COLOR_TYPE_GRAY, 16, false, 1},
                      FormatCase{"SixteenBitRgbInterlaced", PNG_COLOR_TYPE_RGB, 16, true, 3},
                      FormatCase{"Palette", PNG_COLOR_TYPE_PALETTE, 8, false, 3},
                      FormatCase{"GrayAlpha", PNG_COLOR_TYPE_GRAY_ALPHA, 8, false, 1},
                      FormatCase{"Rgba", PNG_COLOR_TYPE_RGB_ALPHA, 8, false, 3},
                      FormatCase{"SixteenBitRgba", PNG_COLOR_TYPE_RGB_ALPHA, 16, false, 3}),
    [](const ::testing::TestParamInfo<FormatCase>& info) { return info.param.name; });

TEST_F(Robustness, InterlacedGivesTheSameOutputsAsPlain) {
  const fs::path plain = input("plain.png", encode(picture(PNG_COLOR_TYPE_RGB, 8, false)));
  const fs::path adam7 = input("adam7.png", encode(picture(PNG_COLOR_TYPE_RGB, 8, true)));
  ASSERT_NE(test::read_file(plain), test::read_file(adam7));
  const CommandResult a =
      test::run_fssim("--input " + quote(plain) + " --seed 5 --outdir " + quote(dir_ / "a"));
  const CommandResult b =
      test::run_fssim("--input " + quote(adam7) + " --seed 5 --outdir " + quote(dir_ / "b"));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* name : {"observed.png", "restored.png", "groundtruth.png", "residual.png"}) {
    EXPECT_TRUE(test::read_file(dir_ / "a" / name) == test::read_file(dir_ / "b" / name)) << name;
  }
}

TEST_F(Robustness, LibpngWarningsAreNotShown) {
  // An ancillary chunk with a bad CRC is discarded by libpng with a warning,
  // which its default handler prints to stderr ("libpng warning: ...").
  Bytes png = encode(picture(PNG_COLOR_TYPE_GRAY, 8));
  Bytes text = {0, 0, 0, 9, 't', 'E', 'X', 't', 'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'x'};
  const std::size_t at = chunk_offset(png, "IDAT");
  write_be32(&text[0], static_cast<std::uint32_t>(text.size() - 8));
  text.insert(text.end(), {0xde, 0xad, 0xbe, 0xef});  // not the CRC
  png.insert(png.begin() + static_cast<long>(at), text.begin(), text.end());
  const fs::path path = input("warning.png", png);
  const CommandResult r =
      test::run_fssim("--input " + quote(path) + " --noise none --outdir " + quote(out_));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
}

TEST_F(Robustness, RunsWithEveryPictureLeaveStderrEmpty) {
  // PLplot prints its warnings on stderr and the cairo driver's libraries
  // (GLib, Pango, Fontconfig) their messages: pictures are drawn with
  // descriptor 2 captured, so a successful run with every picture is silent.
  for (const std::string mode : {"numerical", "analog"}) {
    const CommandResult r = test::run_fssim(with_good_input(
        "--mode " + mode + " --code raskar --trials 2 --sheet --report --outdir " + quote(out_)));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "") << mode;
    EXPECT_TRUE(fs::exists(out_ / "code.png") && fs::exists(out_ / "spectrum.png"));
  }
  const CommandResult sweep =
      test::run_fssim(with_good_input("--velocity 0.5:1:0.25 -o " + quote(dir_ / "s.csv") +
                                      " --plot " + quote(dir_ / "s.png"))
                          .insert(0, "sweep "));
  EXPECT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_EQ(sweep.err, "");
  const CommandResult spectra =
      test::run_fssim("spectra raskar sinc -o " + quote(dir_ / "spectra.png"));
  EXPECT_EQ(spectra.exit_code, 0) << spectra.err;
  EXPECT_EQ(spectra.err, "");
}

// ---------------------------------------------------------------------------
// Code files.

TEST_F(Robustness, CodeFileEmpty) {
  const fs::path code = code_file("empty.txt", "");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "no gains"});
}

TEST_F(Robustness, CodeFileOnlyComments) {
  const fs::path code = code_file("comments.txt", "# a code\n  # to be written\n");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "no gains"});
}

TEST_F(Robustness, CodeFileNonNumericToken) {
  const fs::path code = code_file("word.txt", "1 0 1\n1 one 0\n");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "line 2", "'one'"});
}

TEST_F(Robustness, CodeFileNan) {
  const fs::path code = code_file("nan.txt", "1;\nnan;\n");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "'nan'"});
}

TEST_F(Robustness, CodeFileInfinity) {
  const fs::path code = code_file("inf.txt", "1, -inf, 1");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "'-inf'"});
}

TEST_F(Robustness, CodeFileValueBeyondDoubles) {
  const fs::path code = code_file("big.txt", "1 1e400 1");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "'1e400'", "range"});
}

TEST_F(Robustness, CodeFileBinaryGivesAShortLine) {
  std::string junk = "\x1b[31m\x01\x02\x7f";
  junk += std::string(5000, 'A');
  const fs::path code = code_file("binary.txt", junk);
  const CommandResult r =
      test::run_fssim(with_good_input("--code " + quote(code) + " --outdir " + quote(out_)));
  expect_clean_failure(r, 1, {code.string(), "\\x1b[31m\\x01"});
  EXPECT_LT(r.err.size(), 300u) << r.err;
}

TEST_F(Robustness, CodeFileEndlessIsRefused) {
  expect_failure(with_good_input("--code /dev/zero"), 1, {"/dev/zero", "MiB"});
}

TEST_F(Robustness, CodeFileIsADirectory) {
  fs::create_directory(in_ / "codes");
  expect_failure(with_good_input("--code " + quote(in_ / "codes")), 1,
                 {(in_ / "codes").string(), "directory"});
}

TEST_F(Robustness, CodeLongerThanTheImageAllows) {
  // L = 200 slots blur 200 pixels: the 512-wide image is far too narrow.
  std::string text;
  for (int k = 0; k < 200; ++k) text += (k % 3 == 0 ? "0 " : "1 ");
  const fs::path code = code_file("long.txt", text);
  expect_failure(with_good_input("--code " + quote(code)), 2, {"width 512", "200"});
}

TEST_F(Robustness, AnalogNegativeGain) {
  const fs::path code = code_file("negative.txt", "1 -0.25 1 0 1");
  expect_failure(with_good_input("--mode analog --code " + quote(code)), 2,
                 {code.string(), "-0.25", "[0, 1]"});
}

TEST_F(Robustness, AnalogGainAboveOne) {
  const fs::path code = code_file("above.txt", "1 0 1.5 1");
  expect_failure(with_good_input("--mode analog --code " + quote(code)), 2,
                 {code.string(), "1.5", "[0, 1]"});
}

TEST_F(Robustness, AllZeroCode) {
  const fs::path code = code_file("zeros.txt", "0 0 0; 0, -0\n");
  expect_failure(with_good_input("--code " + quote(code)), 2, {code.string(), "zero"});
}

TEST_F(Robustness, GainsBeyondDoubleArithmeticAreNoSilentNan) {
  // Both parse, but K underflows (1e-320) or overflows (1e308): without a
  // check the RMSE printed is nan and exit status 0.
  const fs::path tiny = code_file("tiny.txt", "1e-320 0 1e-320 1e-320");
  expect_failure(with_good_input("--code " + quote(tiny)), 2, {tiny.string(), "range"});
  const fs::path huge = code_file("huge.txt", "1e308 1e308 1e308");
  expect_failure(with_good_input("--code " + quote(huge)), 2, {huge.string(), "range"});
}

// ---------------------------------------------------------------------------
// Options.

struct OptionCase {
  const char* name;
  const char* arguments;  // after --input <good image>
  const char* culprit;
};

void PrintTo(const OptionCase& c, std::ostream* os) { *os << c.arguments; }

class RobustnessOptions : public Robustness, public ::testing::WithParamInterface<OptionCase> {};

TEST_P(RobustnessOptions, UsageErrorLeavesEverythingAsItWas) {
  expect_failure(with_good_input(GetParam().arguments), 2, {GetParam().culprit});
}

INSTANTIATE_TEST_SUITE_P(
    Options, RobustnessOptions,
    ::testing::Values(
        OptionCase{"UnknownOption", "--bogus 1", "--bogus"},
        OptionCase{"UnknownShortOption", "-q", "-q"},
        OptionCase{"VelocityValueMissing", "--velocity", "--velocity"},
        OptionCase{"SnrValueMissing", "--snr", "--snr"},
        OptionCase{"VelocityNotANumber", "--velocity fast", "--velocity"},
        OptionCase{"VelocityNan", "--velocity NaN", "--velocity"},
        OptionCase{"VelocityMinusInfinity", "--velocity -inf", "--velocity"},
        OptionCase{"SnrZero", "--snr 0", "--snr"}, OptionCase{"SnrNegative", "--snr -3", "--snr"},
        OptionCase{"SnrNan", "--snr nan", "--snr"},
        OptionCase{"SnrHuge", "--snr 1e300", "--snr"},   // lambda2 = inf: NaN noise
        OptionCase{"SnrTiny", "--snr 1e-300", "--snr"},  // lambda2 = 0: NaN noise
        OptionCase{"DtZero", "--dt 0", "--dt"}, OptionCase{"DtNegative", "--dt -0.5", "--dt"},
        OptionCase{"DtTiny", "--dt 1e-300", "--dt"},
        OptionCase{"VelocityEmptiesTheRmseWindow", "--velocity 3", "B = 156"},
        OptionCase{"VelocityBlursMoreThanTheWidth", "--velocity -20", "width 512"},
        OptionCase{"VelocityHuge", "--velocity 1e300", "width 512"},
        OptionCase{"ModeUnknown", "--mode digital", "--mode"},
        OptionCase{"NoiseUnknown", "--noise gaussian", "--noise"},
        OptionCase{"CodeNameUnknown", "--code raskar2", "raskar2"},
        OptionCase{"SeedNegative", "--seed -1", "--seed"},  // CLI11 wraps it to 2^64-1
        OptionCase{"SeedTooLarge", "--seed 18446744073709551616", "--seed"},  // ... saturates
        OptionCase{"SeedNotAnInteger", "--seed 1.5", "--seed"},
        OptionCase{"MarginHuge", "--rmse-margin 2147483647",
                   "--rmse-margin: value 2147483647"},  // int overflow
        OptionCase{"TrialsZero", "--trials 0", "--trials"},
        OptionCase{"TrialsTooMany", "--trials 99999999999", "--trials"},
        OptionCase{"ThreadsNegative", "--threads -2", "--threads"},
        OptionCase{"InputTwice", "--input other.png", "--input"}),
    [](const ::testing::TestParamInfo<OptionCase>& info) { return info.param.name; });

TEST_F(Robustness, InputOptionMissing) { expect_failure("--code raskar", 2, {"--input"}); }

TEST_F(Robustness, InputEmptyPath) { expect_failure("--input ''", 2, {"--input"}); }

TEST_F(Robustness, OutdirEmptyPath) { expect_failure(with_good_input(""), 2, {"--outdir"}, "''"); }

TEST_F(Robustness, FileNameWithANewlineStaysOnOneLine) {
  const fs::path odd = in_ / "two\nlines.png";
  expect_failure("--input " + quote(odd), 1, {"two\\x0alines.png"});
}

// ---------------------------------------------------------------------------
// Output directories.

TEST_F(Robustness, OutdirIsAFile) {
  const fs::path file = input("taken", "a file, not a directory\n");
  expect_failure(with_good_input(""), 1, {file.string(), "not a directory"}, quote(file));
}

TEST_F(Robustness, OutdirBelowAFileCannotBeCreated) {
  const fs::path file = input("plain-file", "x\n");
  const fs::path outdir = file / "out";
  expect_failure(with_good_input(""), 1, {outdir.string()}, quote(outdir));
}

TEST_F(Robustness, OutdirNotWritable) {
  if (::geteuid() != 0) {
    // Mode 0500: files can be listed and read, not created.
    fs::permissions(out_, fs::perms::owner_read | fs::perms::owner_exec);
    expect_failure(with_good_input(""), 1, {out_.string(), "Permission denied"});
    fs::permissions(out_, fs::perms::owner_all);
  } else {
    // Root writes into a 0500 directory anyway; a directory under a regular
    // file cannot be created by anyone.
    const fs::path blocked = input("blocker", "x\n") / "out";
    expect_failure(with_good_input(""), 1, {blocked.string(), "Not a directory"}, quote(blocked));
  }
}

TEST_F(Robustness, WriteFailureMidwayLeavesTheOutdirAsItWas) {
  // Under ulimit -f 2 (1 KiB, root included) code.txt would fit but the PNGs
  // do not: writing fails once some outputs are staged. Unless fssim ignores
  // SIGXFSZ, the signal kills it mid-write and a partial file stays behind.
  const Snapshot before = snapshot(dir_.path());
  const CommandResult r =
      test::run_command("ulimit -f 2 && exec " + quote(std::string(FSSIM_BINARY_PATH)) +
                        " --input " + quote(good_input_) + " --noise none --outdir " + quote(out_));
  expect_clean_failure(r, 1, {out_.string(), "too large"});
  const Snapshot after = snapshot(dir_.path());
  EXPECT_EQ(names_of(after), names_of(before));
  EXPECT_TRUE(after == before);
}

TEST_F(Robustness, RefusesToOverwriteTheCodeFile) {
  // The code file is an input too: --outdir its directory would replace it.
  const fs::path code = out_ / "code.txt";
  test::write_file(code, "# hand-written, with comments\n1 0 1 1 0 0 1 1 1\n");
  expect_failure(with_good_input("--code " + quote(code)), 1, {code.string(), "refusing"});
}

TEST_F(Robustness, RefusesToOverwriteTheInput) {
  const fs::path inside = out_ / "groundtruth.png";
  fs::copy_file(good_input_, inside);
  expect_failure("--input " + quote(inside), 1, {inside.string(), "refusing"});
}

TEST_F(Robustness, NonUtf8FileNameRuns) {
  // File names are bytes; report.json must still be valid JSON.
  const fs::path latin1 = in_ / "caf\xe9.png";
  fs::copy_file(good_input_, latin1);
  const CommandResult r =
      test::run_fssim("--input " + quote(latin1) + " --noise none --outdir " + quote(out_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(test::read_file(out_ / "report.json"));
  EXPECT_EQ(report["input"]["path"], (in_ / "caf\xef\xbf\xbd.png").string());
}

TEST_F(Robustness, UnwritableStdoutIsAnError) {
  // The outputs are written, but the metrics a script reads from stdout are
  // lost: exit status 1, not 0.
  const CommandResult r = test::run_command(
      "{ " + quote(std::string(FSSIM_BINARY_PATH)) + " --input " + quote(good_input_) +
      " --noise none --outdir " + quote(out_) + " >/dev/full; }");
  expect_clean_failure(r, 1, {"standard output"});
  EXPECT_TRUE(fs::exists(out_ / "restored.png"));
}

TEST_F(Robustness, FailedRunThenGoodRun) {
  // After a failure the directory is as it was, and the next run works.
  expect_failure(with_good_input("--snr 0"), 2, {"--snr"});
  const CommandResult r = test::run_fssim(with_good_input("--outdir " + quote(out_)));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> expected = output_file_names();
  expected.push_back("notes.txt");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(test::list_directory(out_), expected);
}

}  // namespace
}  // namespace fss
