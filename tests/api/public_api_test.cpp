// The public API is include/fss: fss/fss.h includes every public header, and
// a public header includes only standard headers and other public headers, so
// no third-party header (nlohmann/json, FFTW, libpng) reaches a user. Each
// header compiling on its own is checked by the public_headers target
// (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;

// Public headers as "fss/<domain>/<name>.h", fss.h left out.
std::set<std::string> public_headers() {
  std::set<std::string> headers;
  const fs::path root = test::source_path("include");
  for (const auto& entry : fs::recursive_directory_iterator(root / "fss")) {
    if (entry.path().extension() != ".h") continue;
    const std::string name = fs::relative(entry.path(), root).generic_string();
    if (name != "fss/fss.h") headers.insert(name);
  }
  return headers;
}

std::vector<std::string> includes_of(const std::string& text, const std::regex& pattern) {
  std::vector<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    found.push_back((*it)[1].str());
  }
  return found;
}

const std::regex kQuoted(R"re(#include\s+"([^"]+)")re");
const std::regex kAngled(R"re(#include\s+<([^>]+)>)re");

TEST(PublicApi, FssHeaderIncludesEveryPublicHeader) {
  const std::string umbrella = test::read_file(test::source_path("include/fss/fss.h"));
  const std::vector<std::string> included = includes_of(umbrella, kQuoted);
  const std::set<std::string> headers = public_headers();
  ASSERT_FALSE(headers.empty());
  for (const std::string& header : headers) {
    EXPECT_NE(std::find(included.begin(), included.end(), header), included.end())
        << "fss/fss.h does not include " << header;
  }
  for (const std::string& name : included) {
    EXPECT_TRUE(headers.count(name)) << "fss/fss.h includes " << name << ", not a public header";
  }
}

TEST(PublicApi, HeadersIncludeOnlyStandardAndPublicHeaders) {
  const std::set<std::string> headers = public_headers();
  // Standard C++ headers have no extension and no directory.
  const std::regex standard(R"([a-z_]+)");
  for (const std::string& header : headers) {
    const std::string text = test::read_file(test::source_path("include/" + header));
    for (const std::string& name : includes_of(text, kQuoted)) {
      EXPECT_TRUE(headers.count(name))
          << header << " includes \"" << name << "\", not a public header";
    }
    for (const std::string& name : includes_of(text, kAngled)) {
      EXPECT_TRUE(std::regex_match(name, standard))
          << header << " includes <" << name << ">, not a standard C++ header";
    }
  }
}

}  // namespace
}  // namespace fss
