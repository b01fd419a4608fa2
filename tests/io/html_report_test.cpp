// Tests of report.html (html_report.h): its links, its escaping, its content,
// and the page as a real browser (headless Chromium) renders it.
#include "io/html_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "fss/io/outputs.h"
#include "fss/io/png_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

// A small real run: 64 x 8 gray, a 4-slot code.
SimulationReport small_report(const std::vector<double>& gains = {1.0, 0.0, 1.0, 1.0},
                              const std::string& name = "short") {
  SimulationOptions options;
  options.threads = 1;
  return Simulate(options, test::make_test_image(64, 8, 1, 5), ShutterCode{name, gains});
}

// Every value of a src="..." or href="..." attribute of `page`.
std::vector<std::string> references(const std::string& page) {
  std::vector<std::string> found;
  const std::regex attribute(R"((?:src|href)\s*=\s*"([^"]*)\")", std::regex::icase);
  for (auto it = std::sregex_iterator(page.begin(), page.end(), attribute);
       it != std::sregex_iterator(); ++it) {
    found.push_back((*it)[1].str());
  }
  return found;
}

std::string format6(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", value);
  return buffer;
}

// ---------------------------------------------------------------------------

TEST(HtmlEscape, EscapesMarkupAndRepairsUtf8) {
  EXPECT_EQ(html_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(html_escape("plain/path_1.png"), "plain/path_1.png");
  EXPECT_EQ(html_escape("ξ α"), "ξ α");  // valid UTF-8 is kept
  EXPECT_EQ(html_escape("bad\xff"), "bad\xEF\xBF\xBD");
  EXPECT_EQ(html_escape("line\nbreak"),
            "line\xEF\xBF\xBD"
            "break");
}

TEST(HtmlReport, LinksEveryOutputAndNothingElse) {
  const SimulationReport report = small_report();
  for (const OutputOptions& options :
       {OutputOptions{true, true, true}, OutputOptions{false, false, true},
        OutputOptions{true, false, true}}) {
    const std::vector<std::string> files = output_file_names(options);
    const std::string page = html_report(report, "in.png", files);
    const std::vector<std::string> links = references(page);
    ASSERT_FALSE(links.empty());
    for (const std::string& link : links) {
      EXPECT_TRUE(std::find(files.begin(), files.end(), link) != files.end())
          << "the page refers to '" << link << "', which is not an output";
    }
    for (const std::string& file : files) {
      EXPECT_TRUE(std::find(links.begin(), links.end(), file) != links.end())
          << "the page does not link " << file;
    }
  }
}

TEST(HtmlReport, IsSelfContained) {
  const std::string page =
      html_report(small_report(), "in.png", output_file_names({true, true, true}));
  EXPECT_THAT(page, testing::StartsWith("<!DOCTYPE html>"));
  EXPECT_THAT(page, HasSubstr("<meta charset=\"utf-8\">"));
  // References are plain relative file names: no scheme, no absolute path,
  // no parent directory.
  for (const std::string& link : references(page)) {
    EXPECT_THAT(link, Not(HasSubstr(":")));
    EXPECT_THAT(link, Not(HasSubstr("/")));
  }
  for (const char* external :
       {"http:", "https:", "<script", "<link", "<iframe", "url(", "@import"}) {
    EXPECT_THAT(page, Not(HasSubstr(external)));
  }
}

TEST(HtmlReport, ShowsTheFiguresThatWereWritten) {
  const SimulationReport report = small_report();
  const std::string all = html_report(report, "in.png", output_file_names({true, false, true}));
  const std::string no_plots =
      html_report(report, "in.png", output_file_names({false, false, true}));
  for (const ReportFigure& figure : report_figures()) {
    EXPECT_THAT(all, HasSubstr("<img src=\"" + std::string(figure.file) + "\""));
  }
  EXPECT_THAT(no_plots, HasSubstr("<img src=\"observed.png\""));
  EXPECT_THAT(no_plots, Not(HasSubstr("<img src=\"code.png\"")));
  EXPECT_THAT(no_plots, Not(HasSubstr("<img src=\"spectrum.png\"")));
  // The four images are shown at the same size: the output's.
  const std::regex size(
      R"(<img src="(observed|restored|groundtruth|residual)\.png" width="52" height="8")");
  EXPECT_EQ(
      std::distance(std::sregex_iterator(all.begin(), all.end(), size), std::sregex_iterator()), 4);
}

TEST(HtmlReport, EscapesUserStrings) {
  const SimulationReport report = small_report({1.0, 0.0, 1.0, 1.0}, "<script>alert(1)</script>");
  const std::string page =
      html_report(report, "dir/\"quoted\" & <odd>.png", output_file_names({true, false, true}));
  EXPECT_THAT(page, Not(HasSubstr("<script")));
  EXPECT_THAT(page, HasSubstr("&lt;script&gt;alert(1)&lt;/script&gt;"));
  EXPECT_THAT(page, HasSubstr("dir/&quot;quoted&quot; &amp; &lt;odd&gt;.png"));
}

TEST(HtmlReport, ListsParametersAndMetrics) {
  const SimulationReport report = small_report();
  ASSERT_TRUE(report.prediction.finite);
  const std::string page = html_report(report, "in.png", output_file_names());
  for (const double value :
       {report.metrics.rmse, report.metrics.psnr, report.metrics.rmse_ci, report.prediction.rmse,
        report.prediction.rmse_noise_free, report.prediction.noise,
        report.prediction.rmse_stationary, report.prediction.sigma}) {
    EXPECT_THAT(page, HasSubstr(format6(value)));
  }
  char snr[32];
  std::snprintf(snr, sizeof snr, "%.3f", report.prediction.snr_level100);
  EXPECT_THAT(page, HasSubstr(snr));
  for (const char* label :
       {"RMSE (measured)", "RMSE_CI", "PSNR", "predicted RMSE (exact expectation)",
        "noise-free RMSE", "stationary approximation", "SNR at level 100", "velocity", "snr",
        "seed"}) {
    EXPECT_THAT(page, HasSubstr(label));
  }
}

TEST(HtmlReport, NonInvertibleCodeHasNoPrediction) {
  const SimulationReport report = small_report({1.0, 1.0, 1.0, 1.0});
  ASSERT_FALSE(report.prediction.finite);
  const std::string page = html_report(report, "in.png", output_file_names());
  EXPECT_THAT(page, HasSubstr("not invertible"));
  EXPECT_THAT(page, Not(HasSubstr("SNR at level 100")));
  EXPECT_THAT(page, HasSubstr("warning:"));
}

TEST(HtmlReport, FigureFramesHaveDistinctColoursNoImageOrPlotHas) {
  std::set<std::vector<int>> colours;
  for (const ReportFigure& f : report_figures()) {
    colours.insert({f.red, f.green, f.blue});
    // A zero component: not gray, and not a blend of the plots' palette.
    EXPECT_TRUE(f.red == 0 || f.green == 0 || f.blue == 0) << f.file;
  }
  EXPECT_EQ(colours.size(), 6u);
  EXPECT_EQ(report_figures().size(), 6u);
}

// ---------------------------------------------------------------------------
// The page in a browser.

constexpr int kWindowWidth = 1600;
constexpr int kWindowHeight = 1900;

struct Box {
  int left = 0, top = 0, width = 0, height = 0;
};

// Bounding box of the largest 4-connected set of pixels of exactly `rgb`.
std::optional<Box> find_frame(const Image& shot, int red, int green, int blue) {
  const int w = shot.width, h = shot.height;
  auto matches = [&](int x, int y) {
    return shot.at(0, y, x) == red && shot.at(1, y, x) == green && shot.at(2, y, x) == blue;
  };
  std::vector<char> seen(static_cast<std::size_t>(w) * h, 0);
  std::optional<Box> best;
  std::size_t best_size = 0;
  std::vector<std::pair<int, int>> stack;
  for (int y0 = 0; y0 < h; ++y0) {
    for (int x0 = 0; x0 < w; ++x0) {
      if (seen[static_cast<std::size_t>(y0) * w + x0] || !matches(x0, y0)) continue;
      int x_min = x0, x_max = x0, y_min = y0, y_max = y0;
      std::size_t size = 0;
      stack.assign(1, {x0, y0});
      seen[static_cast<std::size_t>(y0) * w + x0] = 1;
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        ++size;
        x_min = std::min(x_min, x);
        x_max = std::max(x_max, x);
        y_min = std::min(y_min, y);
        y_max = std::max(y_max, y);
        const int neighbours[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
        for (const auto& [nx, ny] : neighbours) {
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          char& s = seen[static_cast<std::size_t>(ny) * w + nx];
          if (s || !matches(nx, ny)) continue;
          s = 1;
          stack.push_back({nx, ny});
        }
      }
      if (size > best_size) {
        best_size = size;
        best = Box{x_min, y_min, x_max - x_min + 1, y_max - y_min + 1};
      }
    }
  }
  return best;
}

double standard_deviation(const Image& image) {
  double sum = 0.0, square_sum = 0.0;
  for (const double v : image.data) {
    sum += v;
    square_sum += v * v;
  }
  const double n = static_cast<double>(image.data.size());
  return std::sqrt(std::max(0.0, square_sum / n - (sum / n) * (sum / n)));
}

using test::quote;

TEST(HtmlReportInBrowser, EveryFigureLoadsInsideItsFrame) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) {
    const char* ci = std::getenv("CI");
    if (ci != nullptr && *ci != '\0') {
      FAIL() << "CI is set and " << chromium
             << " is missing: install Debian's chromium (scripts/install-deps.sh --browser)";
    }
    GTEST_SKIP() << chromium << " is missing: the report is not checked in a browser "
                 << "(install Debian's chromium to run this test)";
  }
  test::TempDir dir;
  const fs::path out = dir / "out";
  const test::CommandResult run =
      test::run_fssim("--input " + quote(test::source_path("data/camera.png")) +
                      " --code raskar --noise none --report --outdir " + quote(out));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_TRUE(fs::exists(out / "report.html"));

  // A fresh profile and home in the temporary directory; no network, no
  // GPU, scale 1 and sRGB so that pixels are those of the files.
  const fs::path shot_path = dir / "shot.png";
  const std::string command =
      "HOME=" + quote(dir / "home") + " XDG_CONFIG_HOME=" + quote(dir / "config") +
      " XDG_CACHE_HOME=" + quote(dir / "cache") + " timeout -k 10 120 " + chromium.string() +
      " --headless --no-sandbox --disable-gpu --disable-background-networking --no-first-run"
      " --disable-quic --disable-component-update --disable-sync --disable-extensions"
      " --hide-scrollbars --force-device-scale-factor=1 --force-color-profile=srgb"
      " --user-data-dir=" +
      quote(dir / "profile") + " --window-size=" + std::to_string(kWindowWidth) + "," +
      std::to_string(kWindowHeight) + " --screenshot=" + quote(shot_path) + " " +
      quote("file://" + (out / "report.html").string());
  const test::CommandResult browser = test::run_command(command);
  ASSERT_EQ(browser.exit_code, 0) << "chromium failed:\n" << browser.err;
  ASSERT_TRUE(fs::exists(shot_path)) << browser.err;
  const Image shot = read_png(shot_path);
  ASSERT_EQ(shot.width, kWindowWidth);
  ASSERT_EQ(shot.height, kWindowHeight);
  ASSERT_EQ(shot.channels, 3);

  for (const ReportFigure& figure : report_figures()) {
    SCOPED_TRACE(figure.file);
    const std::optional<Box> frame = find_frame(shot, figure.red, figure.green, figure.blue);
    ASSERT_TRUE(frame.has_value()) << "no frame of its colour on the page";
    const Image expected = read_png(out / figure.file);
    ASSERT_GT(standard_deviation(expected), 5.0) << "the file itself is blank";
    // Shown at its own size, inside the frame.
    ASSERT_EQ(frame->width, expected.width + 2 * kReportFrameWidth);
    ASSERT_EQ(frame->height, expected.height + 2 * kReportFrameWidth);
    double difference = 0.0;
    for (int y = 0; y < expected.height; ++y) {
      for (int x = 0; x < expected.width; ++x) {
        for (int c = 0; c < 3; ++c) {
          const double want = expected.at(expected.channels == 1 ? 0 : c, y, x);
          const double got =
              shot.at(c, frame->top + kReportFrameWidth + y, frame->left + kReportFrameWidth + x);
          difference += std::abs(want - got);
        }
      }
    }
    difference /= 3.0 * expected.width * expected.height;
    // A missing image leaves the box white or a broken-image icon: far off.
    EXPECT_LT(difference, 2.0) << "the image in the frame is not the file";
  }
}

}  // namespace
}  // namespace fss
