// The restoration options (fss/model/restoration.h): names, the prior's syntax, the rules.
#include "fss/model/restoration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace fss {
namespace {

TEST(RestorationNames, RoundTrip) {
  for (const auto method :
       {RestorationMethod::kInverse, RestorationMethod::kWiener, RestorationMethod::kTikhonov}) {
    EXPECT_EQ(restoration_method_from_string(to_string(method)), method);
  }
  EXPECT_FALSE(restoration_method_from_string("Wiener").has_value());
  EXPECT_FALSE(restoration_method_from_string("").has_value());
}

TEST(ParsePrior, AcceptsEveryForm) {
  RestorationOptions r;
  std::string error;
  ASSERT_TRUE(parse_prior("oracle", &r, &error)) << error;
  EXPECT_EQ(r.prior, PriorKind::kOracle);
  ASSERT_TRUE(parse_prior("power-law", &r, &error)) << error;
  EXPECT_EQ(r.prior, PriorKind::kPowerLaw);
  EXPECT_EQ(r.prior_exponent, 2.0);
  EXPECT_FALSE(r.prior_level.has_value());
  ASSERT_TRUE(parse_prior("power-law:1.5", &r, &error)) << error;
  EXPECT_EQ(r.prior_exponent, 1.5);
  ASSERT_TRUE(parse_prior("power-law:2:300", &r, &error)) << error;
  EXPECT_EQ(r.prior_exponent, 2.0);
  ASSERT_TRUE(r.prior_level.has_value());
  EXPECT_EQ(*r.prior_level, 300.0);
  EXPECT_EQ(prior_text(r), "power-law:2:300");
}

TEST(ParsePrior, RefusesMalformedText) {
  for (const char* text : {"", "oracle:2", "power", "power-law:", "power-law:x", "power-law:2:",
                           "power-law:-1", "power-law:9", "power-law:2:0", "power-law:2:-3",
                           "power-law:nan", "power-law:2:inf", "power-lawx", "power-law:2:3:4"}) {
    RestorationOptions r;
    std::string error;
    EXPECT_FALSE(parse_prior(text, &r, &error)) << text;
    EXPECT_NE(error.find("expected oracle, power-law"), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST(RestorationOptions, Rules) {
  std::string error;
  RestorationOptions r;
  EXPECT_TRUE(r.IsValid(&error)) << error;
  r.regularization = 0.1;  // the inverse filter takes no lambda
  EXPECT_FALSE(r.IsValid(&error));
  EXPECT_NE(error.find("regularization = 0.1"), std::string::npos) << error;
  r.method = RestorationMethod::kTikhonov;
  EXPECT_TRUE(r.IsValid(&error)) << error;
  for (const double lambda :
       {0.0, 1e-9, 101.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    r.regularization = lambda;
    EXPECT_FALSE(r.IsValid(&error)) << lambda;
  }
  r.regularization.reset();
  r.prior = PriorKind::kOracle;  // Tikhonov takes no prior
  EXPECT_FALSE(r.IsValid(&error));
  EXPECT_NE(error.find("prior = oracle"), std::string::npos) << error;
  r.method = RestorationMethod::kWiener;
  EXPECT_TRUE(r.IsValid(&error)) << error;
  r.prior_level = 10.0;  // the oracle has no level
  EXPECT_FALSE(r.IsValid(&error));
  r.prior = PriorKind::kPowerLaw;
  EXPECT_TRUE(r.IsValid(&error)) << error;
  r.prior_exponent = -0.5;
  EXPECT_FALSE(r.IsValid(&error));
}

TEST(RestorationOptions, Describe) {
  RestorationOptions r;
  EXPECT_EQ(describe(r), "inverse");
  r.method = RestorationMethod::kTikhonov;
  EXPECT_EQ(describe(r), "tikhonov (lambda optimal)");
  r.regularization = 0.001;
  EXPECT_EQ(describe(r), "tikhonov (lambda 0.001)");
  r = {};
  r.method = RestorationMethod::kWiener;
  EXPECT_EQ(describe(r), "wiener (power-law prior, gamma 2)");
  r.prior = PriorKind::kOracle;
  EXPECT_EQ(describe(r), "wiener (oracle prior)");
}

}  // namespace
}  // namespace fss
