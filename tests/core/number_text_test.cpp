// Tests of src/core/number_text.h: parse_finite_number, the one reader of a
// number typed as text (campaign ranges, the command line's ranges).

#include "core/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace fss {
namespace {

TEST(ParseFiniteNumber, ReadsWholeFiniteNumbers) {
  EXPECT_EQ(parse_finite_number("0.5"), 0.5);
  EXPECT_EQ(parse_finite_number("+0.5"), 0.5);
  EXPECT_EQ(parse_finite_number("-3"), -3.0);
  EXPECT_EQ(parse_finite_number("1e-3"), 1e-3);
  EXPECT_EQ(parse_finite_number("0.1"), 0.1);  // the nearest double, as strtod gives it
}

TEST(ParseFiniteNumber, RefusesWhatIsNotAFiniteNumberToItsEnd) {
  for (const std::string text :
       {"", "+", "abc", "1x", " 1", "1 ", "--1", "inf", "-inf", "nan", "1e999", "0x10"}) {
    EXPECT_TRUE(std::isnan(parse_finite_number(text))) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace fss
