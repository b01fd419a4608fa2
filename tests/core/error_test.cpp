// The formatters of values in messages (fss/core/error.h).
#include "fss/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace fss {
namespace {

TEST(FormatExact, ReadsBackAsTheSameDouble) {
  EXPECT_EQ(format_exact(1.0000001), "1.0000001");
  EXPECT_EQ(format_exact(1.0), "1");
  EXPECT_EQ(format_exact(0.1), "0.1");
  EXPECT_EQ(format_exact(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(format_exact(1e300), "1e+300");
  EXPECT_EQ(format_exact(100000.0), "100000");  // as %g writes it, not 1e+05
  EXPECT_EQ(format_exact(-2.5e-320), "-2.5e-320");
  EXPECT_EQ(format_exact(1e-320), "1e-320");  // subnormal: %.6g would write 9.99989e-321
  EXPECT_EQ(format_exact(0.0001), "0.0001");
  EXPECT_EQ(format_exact(123456789.0), "123456789");
  EXPECT_EQ(format_exact(std::nan("")), "nan");
  EXPECT_EQ(format_exact(-std::numeric_limits<double>::infinity()), "-inf");
  // Any double: the text reads back exactly, with no more digits than needed.
  std::srand(7);
  for (int i = 0; i < 2000; ++i) {
    const double x = (std::rand() - RAND_MAX / 2) * std::pow(10.0, std::rand() % 600 - 300) / 7.0;
    EXPECT_EQ(std::strtod(format_exact(x).c_str(), nullptr), x) << format_exact(x);
  }
}

TEST(FormatBytesDistinct, TwoDifferentSizesNeverReadAlike) {
  const double mib = 1024.0 * 1024.0;
  // The usual case keeps format_bytes's one decimal.
  EXPECT_EQ(format_bytes_distinct(12.0 * mib, 10.0 * mib),
            (std::pair<std::string, std::string>{"12.0 MiB", "10.0 MiB"}));
  EXPECT_EQ(format_bytes_distinct(4.6 * mib, 30.0 * 1024.0),
            (std::pair<std::string, std::string>{"4.6 MiB", "30.0 KiB"}));
  // The size needed is rounded up: a limit raised to it is enough.
  EXPECT_EQ(format_bytes_distinct(10.0 * mib + 1000.0, 10.0 * mib),
            (std::pair<std::string, std::string>{"10.1 MiB", "10.0 MiB"}));
  EXPECT_EQ(format_bytes_distinct(163.54 * mib, 100.0 * mib),
            (std::pair<std::string, std::string>{"163.6 MiB", "100.0 MiB"}));
  // Both 10.1 MiB at one decimal: more decimals until they differ.
  EXPECT_EQ(format_bytes_distinct(10.06 * mib, 10.05 * mib),
            (std::pair<std::string, std::string>{"10.06 MiB", "10.05 MiB"}));
  const auto one_byte = format_bytes_distinct(10.0 * mib + 1.0, 10.0 * mib);
  EXPECT_NE(one_byte.first, one_byte.second);
  const auto gib = format_bytes_distinct(1024.0 * mib * 3 + 1.0, 1024.0 * mib * 3);
  EXPECT_NE(gib.first, gib.second);
}

TEST(ShortenForMessage, CutsAndEscapes) {
  EXPECT_EQ(shorten_for_message("abc"), "abc");
  EXPECT_EQ(shorten_for_message("a\nb"), "a\\x0ab");
  EXPECT_EQ(shorten_for_message(std::string(100, 'x')), std::string(40, 'x') + "...");
}

}  // namespace
}  // namespace fss
