// Text helpers shared by the campaign files: numbers in shortest round-trip
// form and JSON string quoting.
#pragma once

#include <string>
#include <string_view>

namespace fss::campaign_text {

// The shortest decimal that reads back as `value` ("0.3", "1e-05", "100");
// "inf", "-inf" and "nan" for the non-finite values.
std::string shortest(double value);

// `text` as a JSON string literal, quotes included.
std::string json_quote(std::string_view text);

// `text` as one CSV field (RFC 4180): quoted when it holds a comma, a quote
// or a line break, quotes doubled.
std::string csv_field(std::string_view text);

}  // namespace fss::campaign_text
