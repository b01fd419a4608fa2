// Every file a subcommand writes (code generate -o, code analyze --json,
// code optimize -o, spectra -o, sweep -o and --plot): never over an input,
// whatever path names it; "-" is standard output; a device, FIFO or
// /proc/self/fd/N is written in place, never replaced; a symbolic link stays
// one; a write error on standard output is exit status 1.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <filesystem>
#include <string>

#include "fss/io/png_io.h"
#include "io/safe_write.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;
using ::testing::HasSubstr;

class SubcommandOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_file(code_, kCode);
    const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(300, 16, 1));
    test::write_file(image_, std::string(png.begin(), png.end()));
  }

  // fssim run in the test directory (relative paths name its files).
  CommandResult fssim(const std::string& arguments) const {
    return test::run_command("cd " + quote(dir_.path()) + " && { '" + FSSIM_BINARY_PATH + "' " +
                             arguments + "; }");
  }

  // A refusal: exit status `status`, one line naming `culprit`, the code
  // file unchanged.
  void expect_refused(const CommandResult& r, int status, const std::string& culprit) const {
    EXPECT_EQ(r.exit_code, status) << r.err;
    EXPECT_THAT(r.err, HasSubstr(culprit));
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_EQ(test::read_file(code_), kCode);
  }

  static constexpr char kCode[] = "1 0 1 1 0 0 1\n";
  test::TempDir dir_;
  fs::path code_ = dir_ / "c.txt";
  fs::path image_ = dir_ / "in.png";
};

TEST_F(SubcommandOutput, AnalyzeJsonNeverOverwritesItsCodeFile) {
  expect_refused(fssim("code analyze c.txt --json c.txt"), 1, "c.txt");
  expect_refused(fssim("code analyze c.txt --json ./c.txt"), 1, "c.txt");
}

TEST_F(SubcommandOutput, SpectraNeverOverwritesACodeFile) {
  expect_refused(fssim("spectra -o c.txt c.txt"), 1, "c.txt");
  fs::create_symlink("c.txt", dir_ / "link.txt");
  expect_refused(fssim("spectra -o link.txt raskar c.txt"), 1, "c.txt");
}

TEST_F(SubcommandOutput, SweepNeverOverwritesItsInputs) {
  expect_refused(fssim("sweep --input in.png --code c.txt -o c.txt"), 1, "c.txt");
  expect_refused(fssim("sweep --input in.png --code c.txt -o x.csv --plot ./c.txt"), 1, "c.txt");
  const std::string png = test::read_file(image_);
  EXPECT_EQ(
      fssim("sweep --input in.png -o ../" + dir_.path().filename().string() + "/in.png").exit_code,
      1);
  EXPECT_EQ(test::read_file(image_), png);
}

TEST_F(SubcommandOutput, SweepOutputAndPlotMustBeTwoFiles) {
  const CommandResult r = fssim("sweep --input in.png -o x.csv --plot ./x.csv");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("same file"));
  EXPECT_FALSE(fs::exists(dir_ / "x.csv"));
  // The SVG that --plot writes beside its PNG: never over an input, nor over --output.
  test::write_file(dir_ / "c.svg", kCode);
  const CommandResult code = fssim("sweep --input in.png --code c.svg -o x.csv --plot c.png");
  EXPECT_EQ(code.exit_code, 1) << code.err;
  EXPECT_THAT(code.err, HasSubstr("writes its SVG to 'c.svg', the input 'c.svg'"));
  EXPECT_EQ(test::read_file(dir_ / "c.svg"), kCode);
  const CommandResult output = fssim("sweep --input in.png -o x.svg --plot x.png");
  EXPECT_EQ(output.exit_code, 2) << output.err;
  EXPECT_THAT(output.err, HasSubstr("the same file as --output"));
  EXPECT_FALSE(fs::exists(dir_ / "x.svg"));
}

// --plot FILE.png writes FILE.svg beside it; --plot FILE.svg the SVG alone.
TEST_F(SubcommandOutput, SweepPlotWritesAnSvgBesideItsPng) {
  const std::string sweep = "sweep --input in.png --code c.txt --velocity 0.5:1:0.5 --trials 2 ";
  const CommandResult both = fssim(sweep + "-o a.csv --plot a.png");
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_THAT(both.out, HasSubstr("Plot: a.png\nPlot: a.svg\n"));
  EXPECT_EQ(test::read_file(dir_ / "a.png").substr(1, 3), "PNG");
  EXPECT_EQ(test::read_file(dir_ / "a.svg").rfind("<svg", 0), 0u);
  const CommandResult svg = fssim(sweep + "-o b.csv --plot b.SVG");
  ASSERT_EQ(svg.exit_code, 0) << svg.err;
  EXPECT_EQ(test::read_file(dir_ / "b.SVG"), test::read_file(dir_ / "a.svg"));
  EXPECT_FALSE(fs::exists(dir_ / "b.png"));
}

TEST_F(SubcommandOutput, DashIsStandardOutput) {
  CommandResult r = fssim("code generate sinc --length 4 -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, ::testing::StartsWith("# sinc code, L = 4"));
  r = fssim("code analyze raskar --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, 2), "{\n");
  r = fssim("spectra -o - raskar");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(1, 3), "PNG");
  r = fssim("sweep --input in.png -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, ::testing::StartsWith("velocity,snr,"));
  r = fssim("code optimize --length 4 --velocity 1 --restarts 1 --iterations 5 -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, ::testing::StartsWith("# optimized"));
  EXPECT_FALSE(fs::exists(dir_ / "-"));
}

TEST_F(SubcommandOutput, FullStandardOutputIsExitStatusOne) {
  for (const std::string command :
       {"code generate sinc --length 200", "code analyze raskar", "spectra -o s.png raskar",
        "sweep --input in.png -o x.csv", "code generate sinc --length 4 -o -"}) {
    const CommandResult r = fssim(command + " >/dev/full");
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("standard output")) << command;
  }
}

TEST_F(SubcommandOutput, DevicesAndOpenFilesAreWrittenInPlace) {
  struct stat before {};
  ASSERT_EQ(::stat("/dev/null", &before), 0);
  EXPECT_EQ(fssim("code generate sinc --length 4 -o /dev/null").exit_code, 0);
  struct stat after {};
  ASSERT_EQ(::stat("/dev/null", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode));
  EXPECT_EQ(after.st_ino, before.st_ino);

  fs::create_symlink("/proc/self/fd/1", dir_ / "to-stdout");
  const CommandResult r = fssim("code generate sinc --length 4 -o to-stdout");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("# sinc code, L = 4"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "to-stdout"));
}

TEST_F(SubcommandOutput, FifoIsWrittenInPlace) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const CommandResult r =
      test::run_command("cd " + quote(dir_.path()) + " && { cat fifo > got & '" +
                        FSSIM_BINARY_PATH + "' code generate sinc --length 4 -o fifo; wait; }");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_THAT(test::read_file(dir_ / "got"), ::testing::StartsWith("# sinc code, L = 4"));
}

TEST_F(SubcommandOutput, SymbolicLinkToAFileStaysALink) {
  test::write_file(dir_ / "real.txt", "old\n");
  fs::create_symlink("real.txt", dir_ / "link.txt");
  ASSERT_EQ(fssim("code generate sinc --length 4 -o link.txt").exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
  EXPECT_THAT(test::read_file(dir_ / "real.txt"), ::testing::StartsWith("# sinc code, L = 4"));
  EXPECT_EQ(test::list_directory(dir_.path()),
            (std::vector<std::string>{"c.txt", "in.png", "link.txt", "real.txt"}));
}

// Work is bounded before it starts (issue 12): a code longer than
// kMaxCodeLength is refused while it is read, and the search and grid sizes
// have upper bounds; each refusal is one line.
TEST_F(SubcommandOutput, LongCodesAndHugeEffortsAreRefusedAtOnce) {
  std::string gains;
  for (int i = 0; i < 1000000; ++i) gains += "0.5\n";
  test::write_file(dir_ / "long.txt", gains);
  for (const std::string command : {"code analyze long.txt", "spectra -o s.png long.txt",
                                    "--input in.png --code long.txt --outdir out"}) {
    const CommandResult r = fssim(command);
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("more than 1024 gains")) << command;
    EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  for (const auto& [command, option] : std::vector<std::pair<std::string, std::string>>{
           {"code analyze raskar --grid 2147483647", "--grid"},
           {"code optimize --length 8 --velocity 1 --restarts 1000000000", "--restarts"},
           {"code optimize --length 8 --velocity 1 --iterations 1000000000", "--iterations"},
           {"code optimize --length 100000 --velocity 1", "--length"},
           {"code generate sinc --length 10000", "--length"}}) {
    const CommandResult r = fssim(command);
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr(option)) << command;
  }
}

TEST_F(SubcommandOutput, SeedsAreParsedStrictly) {
  for (const std::string command :
       {"code generate random --length 4 --seed", "code optimize --length 4 --velocity 1 --seed"}) {
    for (const std::string seed : {"-1", "18446744073709551616", "1e3"}) {
      const CommandResult r = fssim(command + " " + seed);
      EXPECT_EQ(r.exit_code, 2) << command << " " << seed << ": " << r.err;
      EXPECT_THAT(r.err, HasSubstr("--seed")) << r.err;
    }
  }
}

TEST_F(SubcommandOutput, MaxMemoryIsParsedStrictly) {
  for (const std::string value : {"0.5", "1e-300", "''", "0.0001K"}) {
    const CommandResult r = fssim("--input in.png --outdir out --max-memory " + value);
    EXPECT_EQ(r.exit_code, 2) << value << ": " << r.err;
    EXPECT_THAT(r.err, HasSubstr("--max-memory")) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
  }
}

TEST_F(SubcommandOutput, ParseErrorsAreInFssimsWords) {
  CommandResult r = fssim("--input in.png 3 -x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("unexpected arguments: 3 -x"));
  r = fssim("code analyze raskar --velocity");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("--velocity needs a value"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("FLOAT")));
}

TEST_F(SubcommandOutput, HelpShowsPlainValueKinds) {
  for (const std::string command : {"--help", "code analyze --help", "code optimize --help",
                                    "code generate --help", "spectra --help", "sweep --help"}) {
    const CommandResult r = fssim(command);
    EXPECT_EQ(r.exit_code, 0) << command;
    for (const char* cli11 : {"FLOAT", "FINITE", "POSITIVE", "UINT64", "TEXT:PATH", "INTEGER:"}) {
      EXPECT_THAT(r.out, ::testing::Not(HasSubstr(cli11))) << command;
    }
  }
}

TEST_F(SubcommandOutput, SweepHasTheMemoryGuard) {
  const CommandResult r = fssim("sweep --input in.png -o x.csv --max-memory 1K");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("raise it with --max-memory"));
  EXPECT_FALSE(fs::exists(dir_ / "x.csv"));
}

TEST_F(SubcommandOutput, InvisibleAndInvalidBytesAreShownEscaped) {
  test::write_file(dir_ / "bom.txt",
                   "\xEF\xBB\xBF"
                   "1 0 1\n");
  CommandResult r = fssim("code analyze bom.txt");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("'\\xef\\xbb\\xbf1' is not a number"));
  test::write_file(dir_ / "bad.txt", "1 \xFF 1\n");
  r = fssim("code analyze bad.txt");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("'\\xff'"));
}

// A 4000 x 4000 gray PNG whose IDAT has a bad CRC: decoding would fail on
// it, so a refusal naming the run's memory comes from the header alone.
std::string png_with_bad_idat(std::uint32_t width, std::uint32_t height) {
  const auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  const auto chunk = [&](const std::string& type, const std::string& data, bool good_crc) {
    const std::string body = type + data;
    uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), body.size());
    if (!good_crc) crc ^= 1;
    return be32(static_cast<std::uint32_t>(data.size())) + body +
           be32(static_cast<std::uint32_t>(crc));
  };
  const std::string raw(static_cast<std::size_t>(width + 1) * height, '\0');
  uLongf size = compressBound(raw.size());
  std::string packed(size, '\0');
  compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
            reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 9);
  packed.resize(size);
  const std::string ihdr = be32(width) + be32(height) + std::string("\x08\x00\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr, true) +
         chunk("IDAT", packed, false) + chunk("IEND", "", true);
}

TEST_F(SubcommandOutput, RunTooLargeForTheLimitIsRefusedFromTheHeader) {
  test::write_file(dir_ / "big.png", png_with_bad_idat(4000, 4000));
  const CommandResult r = fssim("--input big.png --outdir out --max-memory 300M");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("input 'big.png': a run on this 4000 x 4000 x 1 image needs about"));
  EXPECT_THAT(r.err, HasSubstr("raise it with --max-memory"));
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  // Within the limit the header passes and decoding finds the bad CRC.
  const CommandResult decoded = fssim("--input big.png --outdir out --max-memory 0");
  EXPECT_EQ(decoded.exit_code, 1) << decoded.err;
  EXPECT_THAT(decoded.err, ::testing::Not(HasSubstr("memory")));
}

TEST(SafeWrite, RefusesDirectoriesAndDanglingLinksAndKeepsPermissions) {
  const test::TempDir dir;
  EXPECT_TRUE(test::throws_error([&] { write_file_safely(dir.path(), "x"); }, ErrorKind::kRuntime,
                                 {"directory"}));
  fs::create_symlink("missing", dir / "dangling");
  EXPECT_TRUE(test::throws_error([&] { write_file_safely(dir / "dangling", "x"); },
                                 ErrorKind::kRuntime, {"missing"}));
  const fs::path file = dir / "f";
  test::write_file(file, "old");
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write);
  write_file_safely(file, "new");
  EXPECT_EQ(test::read_file(file), "new");
  EXPECT_EQ(fs::status(file).permissions(), fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_TRUE(
      test::throws_error([&] { write_file_safely(file, "x", {(dir / "." / "f").string()}); },
                         ErrorKind::kRuntime, {"refusing"}));
  EXPECT_EQ(test::read_file(file), "new");
}

// A file in missing folders (sweep -o out/runs/x.csv) creates them; a failure removes them again.
TEST(SafeWrite, CreatesMissingFoldersAndRemovesThemOnAFailure) {
  const test::TempDir dir;
  EXPECT_TRUE(test::throws_error([&] { write_file_safely(dir / "out" / "x.csv", "x"); },
                                 ErrorKind::kRuntime, {"x.csv"}));
  write_file_in_folders(dir / "out" / "runs" / "x.csv", "a,b\n");
  EXPECT_EQ(test::read_file(dir / "out" / "runs" / "x.csv"), "a,b\n");
  test::write_file(dir / "file", "not a folder");
  EXPECT_TRUE(test::throws_error([&] { write_file_in_folders(dir / "file" / "x.csv", "x"); },
                                 ErrorKind::kRuntime, {"file/x.csv"}));
  // A name that fits but whose temporary (".NAME.fssim-PID-N.tmp") does not: the write fails
  // after the folders were made.
  const std::string name(240, 'n');
  EXPECT_TRUE(test::throws_error([&] { write_file_in_folders(dir / "new" / "deeper" / name, "x"); },
                                 ErrorKind::kRuntime, {"cannot create a file in"}));
  EXPECT_FALSE(fs::exists(dir / "new"));
}

TEST(SafeWrite, SameFileComparesFilesNotSpellings) {
  const test::TempDir dir;
  test::write_file(dir / "a", "a");
  fs::create_hard_link(dir / "a", dir / "hard");
  EXPECT_TRUE(same_file(dir / "a", dir / "hard"));
  EXPECT_TRUE(same_file(dir / "new", dir / "." / "new"));
  EXPECT_FALSE(same_file(dir / "a", dir / "new"));
}

}  // namespace
}  // namespace fss
