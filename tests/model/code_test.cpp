// Tests of fss/code.h: the code text format, the built-in codes of the paper
// (docs/method.md §7), the gain sums and the shutter mode names.

#include "fss/model/code.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "support/test_util.h"

namespace fss {
namespace {

using Gains = std::vector<double>;

// gtest only (no gmock): substring check with a readable failure message.
::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// The Agrawal-Raskar binary code as written in docs/method.md §7.
std::vector<double> raskar_gains() {
  const std::string bits = "1010000111000001010000110011110111010111001001100111";
  std::vector<double> gains;
  for (const char bit : bits) gains.push_back(bit == '1' ? 1.0 : 0.0);
  return gains;
}

// True when `message` contains "line <number>" not followed by another digit,
// so that "line 2" does not match "line 23".
bool names_line(const std::string& message, int number) {
  const std::string needle = "line " + std::to_string(number);
  for (std::size_t pos = message.find(needle); pos != std::string::npos;
       pos = message.find(needle, pos + 1)) {
    const std::size_t after = pos + needle.size();
    if (after == message.size() || !std::isdigit(static_cast<unsigned char>(message[after]))) {
      return true;
    }
  }
  return false;
}

// Parses `text` expecting a runtime fss::Error; returns its message.
std::string parse_error_message(const std::string& text, const std::string& origin) {
  try {
    parse_code_text(text, origin);
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kRuntime) << "for text '" << text << "'";
    return error.what();
  }
  ADD_FAILURE() << "parse_code_text accepted '" << text << "'";
  return "";
}

TEST(ParseCodeText, WhitespaceSeparated) {
  const ShutterCode code = parse_code_text("1 0.5\t-2\n\n  3\v4\f5  ", "ws");
  EXPECT_EQ(code.gains, (Gains{1.0, 0.5, -2.0, 3.0, 4.0, 5.0}));
  EXPECT_EQ(code.length(), 6);
  EXPECT_EQ(code.name, "ws");
}

TEST(ParseCodeText, CommasAndSemicolons) {
  EXPECT_EQ(parse_code_text("1,2, 3 ,4", "c").gains, (Gains{1.0, 2.0, 3.0, 4.0}));
  EXPECT_EQ(parse_code_text("1;2; 3 ;4;", "s").gains, (Gains{1.0, 2.0, 3.0, 4.0}));
  EXPECT_EQ(parse_code_text("1,0.25;\n-1", "m").gains, (Gains{1.0, 0.25, -1.0}));
}

TEST(ParseCodeText, Comments) {
  const std::string text =
      "# header line, with 7 numbers 8 and separators;\n"
      "1 2 # trailing comment 99\n"
      "#3\n"
      "4#glued comment 5\n"
      "   # indented comment\n"
      "6";
  EXPECT_EQ(parse_code_text(text, "comments").gains, (Gains{1.0, 2.0, 4.0, 6.0}));
}

TEST(ParseCodeText, CrlfLineEnds) {
  EXPECT_EQ(parse_code_text("1;\r\n0;\r\n0.5;\r\n", "crlf").gains, (Gains{1.0, 0.0, 0.5}));
  EXPECT_EQ(parse_code_text("# c\r\n2\r\n3 # c\r\n", "crlf").gains, (Gains{2.0, 3.0}));
  // The line count must not be thrown off by the '\r'.
  const std::string message = parse_error_message("1\r\n2\r\nbad\r\n", "crlf.txt");
  EXPECT_TRUE(names_line(message, 3)) << message;
}

TEST(ParseCodeText, LeadingPlus) {
  EXPECT_EQ(parse_code_text("+1 +0.5 -2 +3e-1", "plus").gains, (Gains{1.0, 0.5, -2.0, 0.3}));
}

TEST(ParseCodeText, ValuesAreExactDoubles) {
  // The shortest decimal text of a double reads back to that double.
  const ShutterCode code = parse_code_text("0.1 -0.0072629 1e-300 123456.789", "exact");
  EXPECT_EQ(code.gains, (Gains{0.1, -0.0072629, 1e-300, 123456.789}));
}

TEST(ParseCodeText, ReferenceCodeTxt) {
  // The reference program's code.txt: "1;" per line.
  const auto path = test::fixture_path("camera_numerical_raskar_v1_noisefree/code.txt");
  const ShutterCode code = parse_code_text(test::read_file(path), "code.txt");
  ASSERT_EQ(code.length(), 52);
  EXPECT_EQ(code.gains, raskar_gains());
}

TEST(ParseCodeText, EmptyTextIsAnError) {
  for (const std::string text : {"", "   ", "\n\n", " ,;\r\n;,", "\t"}) {
    const std::string message = parse_error_message(text, "empty-origin.txt");
    EXPECT_TRUE(Contains(message, "empty-origin.txt")) << "text '" << text << "'";
  }
}

TEST(ParseCodeText, OnlyCommentsIsAnError) {
  for (const std::string text : {"# 1 2 3", "# a\n# b\n", "  # x;1,2\r\n#\r\n"}) {
    const std::string message = parse_error_message(text, "comments-origin.txt");
    EXPECT_TRUE(Contains(message, "comments-origin.txt")) << "text '" << text << "'";
  }
}

TEST(ParseCodeText, BadTokenErrorNamesOriginLineAndToken) {
  struct Case {
    std::string text;
    int line;
    std::string token;
  };
  const std::vector<Case> cases = {
      {"0.5x", 1, "0.5x"},
      {"1 2\n0.5x 3", 2, "0.5x"},
      {"1;\n0;\n1;\nabc;\n", 4, "abc"},
      {"# comment 1\n\n1, 2, x1", 3, "x1"},
      {"1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n11\n12\n13\n14\n15\n16\n17\n18\n19\n20\n21\n22\n1..2", 23,
       "1..2"},
      {"nan", 1, "nan"},
      {"1 NaN", 1, "NaN"},
      {"1\ninf", 2, "inf"},
      {"-inf", 1, "-inf"},
      {"1\n\ninfinity", 3, "infinity"},
      {"1e999", 1, "1e999"},
      {"0 -1e999", 1, "-1e999"},
      {"+-1", 1, "+-1"},
      {"+", 1, "+"},
      {"1 - 2", 1, "-"},
  };
  for (const Case& c : cases) {
    const std::string message = parse_error_message(c.text, "origin-name.txt");
    EXPECT_TRUE(Contains(message, "origin-name.txt")) << "text '" << c.text << "'";
    EXPECT_TRUE(Contains(message, "'" + c.token + "'")) << "text '" << c.text << "'";
    EXPECT_TRUE(names_line(message, c.line))
        << "text '" << c.text << "' expected line " << c.line << ": " << message;
  }
}

TEST(ParseCodeText, OutOfRangeValueSaysSo) {
  for (const std::string token : {"1e999", "-1e400", "+2e308"}) {
    const std::string message = parse_error_message("1 " + token, "range.txt");
    EXPECT_TRUE(Contains(message, "'" + token + "'"));
    EXPECT_TRUE(Contains(message, "out of the range")) << message;
  }
}

TEST(ParseCodeText, BinaryTokenIsShownShortOnOneLine) {
  // A binary file given as a code: the message quotes 40 bytes of the token,
  // control bytes escaped, rather than 10 kB of terminal escapes.
  std::string text = "1 0 \x1b[2J\x01";
  text += std::string(10000, 'Z');
  const std::string message = parse_error_message(text, "binary.bin");
  EXPECT_LT(message.size(), 200u) << message;
  for (const char c : message) {
    const auto byte = static_cast<unsigned char>(c);
    EXPECT_TRUE(byte >= 0x20 && byte != 0x7f) << "control byte " << int{byte} << " in message";
  }
  EXPECT_TRUE(Contains(message, "'\\x1b[2J\\x01ZZZZ"));
  EXPECT_TRUE(Contains(message, "ZZZ...'"));
}

TEST(BuiltinCodes, NamesAreThePapersSix) {
  std::vector<std::string> names = builtin_code_names();
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"accumulation", "mip", "random", "raskar", "sinc",
                                             "snapshot"}));
}

TEST(BuiltinCodes, EachHas52GainsAndItsName) {
  for (const std::string& name : builtin_code_names()) {
    const auto code = builtin_code(name);
    ASSERT_TRUE(code.has_value()) << name;
    EXPECT_EQ(code->name, name);
    EXPECT_EQ(code->length(), 52) << name;
  }
  EXPECT_FALSE(builtin_code("Raskar").has_value());
  EXPECT_FALSE(builtin_code("").has_value());
  EXPECT_FALSE(builtin_code("codes/raskar.txt").has_value());
}

TEST(BuiltinCodes, GainsEqualThePapersListExactly) {
  for (const std::string name : {"snapshot", "accumulation", "raskar", "random", "mip", "sinc"}) {
    const std::vector<double> gains = test::paper_gains(name);
    ASSERT_EQ(gains.size(), 52u) << name;
    const auto code = builtin_code(name);
    ASSERT_TRUE(code.has_value()) << name;
    EXPECT_EQ(code->gains, gains) << name;
  }
  EXPECT_EQ(test::paper_gains("raskar"), raskar_gains());
}

TEST(BuiltinCodes, SnapshotAndAccumulation) {
  std::vector<double> snapshot(52, 0.0);
  snapshot[0] = 1.0;
  EXPECT_EQ(builtin_code("snapshot")->gains, snapshot);
  EXPECT_EQ(builtin_code("accumulation")->gains, std::vector<double>(52, 1.0));
}

TEST(BuiltinCodes, NormalizedL1MatchesSpec) {
  EXPECT_DOUBLE_EQ(normalized_l1(builtin_code("snapshot")->gains), 1.0);
  EXPECT_DOUBLE_EQ(normalized_l1(builtin_code("accumulation")->gains), 52.0);
  EXPECT_DOUBLE_EQ(normalized_l1(builtin_code("raskar")->gains), 26.0);
  // docs/method.md §7 gives these to 4 decimals ("~6.0031", "~1.3364").
  EXPECT_NEAR(normalized_l1(builtin_code("mip")->gains), 6.0031, 1e-3);
  EXPECT_NEAR(normalized_l1(builtin_code("sinc")->gains), 1.3364, 1e-3);
}

TEST(GainSums, SmallVector) {
  const std::vector<double> gains = {1.0, -2.0, 3.5, 0.0};
  EXPECT_DOUBLE_EQ(gain_sum(gains), 2.5);
  EXPECT_DOUBLE_EQ(gain_square_sum(gains), 17.25);
  EXPECT_DOUBLE_EQ(gain_max_abs(gains), 3.5);
  EXPECT_DOUBLE_EQ(normalized_l1(gains), 6.5 / 3.5);
  EXPECT_DOUBLE_EQ(gain_max_abs({-4.0, 1.0}), 4.0);
  EXPECT_EQ(normalized_l1({0.0, 0.0}), 0.0);
}

TEST(FormatCodeTxt, ReferenceLayout) {
  ShutterCode code;
  code.gains = {1.0, 0.0, -0.5};
  EXPECT_EQ(format_code_txt(code), "1;\n0;\n-0.5;\n");
}

TEST(FormatCodeTxt, RoundTripsExactly) {
  for (const std::string name : {"random", "mip", "sinc", "raskar"}) {
    const ShutterCode code = *builtin_code(name);
    const std::string text = format_code_txt(code);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 52) << name;
    EXPECT_EQ(parse_code_text(text, name).gains, code.gains) << name;
  }
  // Values whose shortest text is long must survive too.
  ShutterCode awkward;
  awkward.gains = {0.1 + 0.2, 1.0 / 3.0, -2.0 / 7.0, 1e-17, 6.02214076e23, -0.0};
  EXPECT_EQ(parse_code_text(format_code_txt(awkward), "awkward").gains, awkward.gains);
}

TEST(LoadCode, BuiltinName) {
  const ShutterCode code = load_code("raskar");
  EXPECT_EQ(code.name, "raskar");
  EXPECT_EQ(code.gains, raskar_gains());
}

TEST(LoadCode, File) {
  test::TempDir dir;
  const auto path = dir / "my code.txt";
  test::write_file(path, "# mine\n0.5, 1\r\n-0.25;\n");
  const ShutterCode code = load_code(path.string());
  EXPECT_EQ(code.name, path.string());
  EXPECT_EQ(code.gains, (Gains{0.5, 1.0, -0.25}));
}

TEST(LoadCode, ReferenceCodeTxtFile) {
  const auto path = test::fixture_path("camera_numerical_raskar_v1_noisefree/code.txt");
  EXPECT_EQ(load_code(path.string()).gains, raskar_gains());
}

TEST(LoadCode, BadFileContentNamesTheFile) {
  test::TempDir dir;
  const auto path = dir / "bad.txt";
  test::write_file(path, "1\n2\nx\n");
  try {
    load_code(path.string());
    FAIL() << "bad content accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kRuntime);
    EXPECT_TRUE(Contains(error.what(), path.string()));
    EXPECT_TRUE(names_line(error.what(), 3)) << error.what();
  }
}

TEST(LoadCode, UnknownNameIsAUsageErrorListingTheBuiltins) {
  test::TempDir dir;
  const std::string missing = (dir / "no-such-code").string();
  try {
    load_code(missing);
    FAIL() << "unknown code accepted";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kUsage);
    const std::string message = error.what();
    EXPECT_TRUE(Contains(message, missing));
    for (const std::string& name : builtin_code_names()) EXPECT_TRUE(Contains(message, name));
    for (const char* name : {"snapshot", "accumulation", "raskar", "random", "mip", "sinc"}) {
      EXPECT_TRUE(Contains(message, name));
    }
  }
}

TEST(LoadCode, DirectoryThrows) {
  test::TempDir dir;
  EXPECT_TRUE(test::throws_error([&] { load_code(dir.path().string()); }, ErrorKind::kRuntime,
                                 {dir.path().string()}));
}

TEST(ShutterMode, RoundTrip) {
  for (const ShutterMode mode : {ShutterMode::kNumerical, ShutterMode::kAnalog}) {
    const auto parsed = shutter_mode_from_string(to_string(mode));
    ASSERT_TRUE(parsed.has_value()) << to_string(mode);
    EXPECT_EQ(*parsed, mode);
  }
  EXPECT_NE(to_string(ShutterMode::kNumerical), to_string(ShutterMode::kAnalog));
  EXPECT_EQ(shutter_mode_from_string("numerical"), ShutterMode::kNumerical);
  EXPECT_EQ(shutter_mode_from_string("analog"), ShutterMode::kAnalog);
}

TEST(ShutterMode, RejectsOtherSpellings) {
  for (const char* text : {"Analog", "ANALOG", "Numerical", "analog ", " analog", "", "digital"}) {
    EXPECT_FALSE(shutter_mode_from_string(text).has_value()) << "'" << text << "'";
  }
}

TEST(LoadCode, FileLargerThanTheLimitIsRefused) {
  // Without a limit, /dev/zero or a huge file is read until memory runs out.
  test::TempDir dir;
  const auto path = dir / "huge.txt";
  std::string text;
  while (text.size() <= kMaxCodeFileBytes) text += "1 0 ";
  test::write_file(path, text);
  EXPECT_TRUE(test::throws_error([&] { load_code(path.string()); }, ErrorKind::kRuntime,
                                 {path.string(), "MiB"}));
}

// A name with a NUL: the file system would open the path up to the NUL, and
// the message was cut there. Refused, the NUL written as \x00.
TEST(LoadCode, NameWithANulIsRefusedAndEscaped) {
  test::TempDir dir;
  test::write_file(dir / "a", "1 0 1\n");
  const std::string name = (dir / "a").string() + std::string(1, '\0') + "b";
  const auto error = test::error_of([&] { load_code(name, "--code"); });
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->kind(), ErrorKind::kUsage);
  EXPECT_EQ(std::string(error->what()), "--code '" + (dir / "a").string() +
                                            "\\x00b' holds a NUL byte: no built-in code or file "
                                            "name has one");
}

}  // namespace
}  // namespace fss
