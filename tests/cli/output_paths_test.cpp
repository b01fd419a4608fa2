// No command writes over one of its inputs: every output path of every
// command given the path of one of its inputs (the same name, a hard link,
// a symbolic link) is refused with exit 1 or 2 and one line on stderr, and
// the input keeps its bytes. (The campaign commands have their own cases in
// campaign_cli_test.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "fss/io/tiff_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
    text.replace(at, from.size(), to);
    at += to.size();
  }
  return text;
}

class OutputPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(900, 8, 1));
    image_bytes_ = std::string(png.begin(), png.end());
    code_bytes_ = "1\n0\n1\n1\n0\n1\n";
  }

  // Runs `arguments` ({IN}: the image, {CODE}: a code file) with `target`
  // ({IN} or {CODE}) reached as itself, through a hard link and through a
  // symbolic link, and expects a refusal that leaves both inputs as they were.
  void expect_refused(const std::string& arguments, const std::string& target) {
    for (const char* way : {"same", "hard", "symbolic"}) {
      fs::remove_all(dir_ / "d");
      fs::create_directories(dir_ / "d");
      const fs::path image = dir_ / "d" / "in.png";
      const fs::path code = dir_ / "d" / "code.txt";
      test::write_file(image, image_bytes_);
      test::write_file(code, code_bytes_);
      const fs::path input = target == "{IN}" ? image : code;
      fs::path output = input;
      if (std::string(way) == "hard") fs::create_hard_link(input, output = dir_ / "d" / "hard");
      if (std::string(way) == "symbolic") fs::create_symlink(input, output = dir_ / "d" / "sym");
      std::string line = replace_all(arguments, "{OUT}", quote(output));
      line = replace_all(replace_all(line, "{IN}", quote(image)), "{CODE}", quote(code));
      const CommandResult r = test::run_fssim(line);
      EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << line << " (" << way << ")";
      EXPECT_EQ(test::lines_of(r.err).size(), 1u) << line << ": " << r.err;
      EXPECT_EQ(test::read_file(image), image_bytes_) << line << " (" << way << ")";
      EXPECT_EQ(test::read_file(code), code_bytes_) << line << " (" << way << ")";
    }
  }

  test::TempDir dir_;
  std::string image_bytes_;
  std::string code_bytes_;
};

TEST_F(OutputPaths, SweepNeverWritesOverItsImageOrCode) {
  const std::string sweep = "sweep -i {IN} -c {CODE} --noise none -v 1:2:1 ";
  expect_refused(sweep + "-o {OUT}", "{IN}");
  expect_refused(sweep + "-o {OUT}", "{CODE}");
  expect_refused(sweep + "-o - --plot {OUT}", "{IN}");
  expect_refused(sweep + "-o - --plot {OUT}", "{CODE}");
}

TEST_F(OutputPaths, SpectraNeverWritesOverACode) {
  expect_refused("spectra raskar {CODE} -o {OUT}", "{CODE}");
}

TEST_F(OutputPaths, CodeAnalyzeNeverWritesOverItsCode) {
  expect_refused("code analyze {CODE} --json {OUT}", "{CODE}");
}

// The simulator's outputs have fixed names in --outdir: an input that has
// one of those names there is never replaced.
TEST_F(OutputPaths, SimulatorNeverReplacesItsImageOrCode) {
  for (const char* name : {"observed.png", "groundtruth.png", "report.json", "code.txt"}) {
    for (const char* which : {"image", "code"}) {
      test::TempDir dir;
      const fs::path out = dir / "out";
      fs::create_directories(out);
      const fs::path input = out / name;
      const bool image = std::string(which) == "image";
      test::write_file(input, image ? image_bytes_ : code_bytes_);
      const fs::path other = dir / (image ? "code.txt" : "in.png");
      test::write_file(other, image ? code_bytes_ : image_bytes_);
      const fs::path& image_path = image ? input : other;
      const fs::path& code_path = image ? other : input;
      const CommandResult r = test::run_fssim("-i " + quote(image_path) + " -c " +
                                              quote(code_path) + " --no-plots -o " + quote(out));
      EXPECT_EQ(r.exit_code, 1) << name << " " << which << ": " << r.err;
      EXPECT_EQ(test::read_file(image_path), image_bytes_) << name << " " << which;
      EXPECT_EQ(test::read_file(code_path), code_bytes_) << name << " " << which;
    }
  }
}

// An input named like an output this run does not write (an earlier run's
// sheet.png or observed.tif, which goes with the old set) is kept.
TEST_F(OutputPaths, SimulatorNeverRemovesAnInputAsAStaleOutput) {
  for (const char* name : {"sheet.png", "observed.tif", "code.png"}) {
    test::TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directories(out);
    const fs::path input = out / name;
    const bool tiff = std::string(name).ends_with(".tif");
    const Image image = test::make_test_image(900, 8, 1);
    const std::vector<std::uint8_t> bytes = tiff ? encode_tiff_float(image) : encode_png8(image);
    test::write_file(input, std::string(bytes.begin(), bytes.end()));
    const CommandResult r = test::run_fssim("-i " + quote(input) + " --no-plots -o " + quote(out));
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    ASSERT_TRUE(fs::exists(input)) << name << " was removed";
    EXPECT_EQ(test::read_file(input), std::string(bytes.begin(), bytes.end())) << name;
  }
}

}  // namespace
}  // namespace fss
