// Tests of a campaign's figures (fss/campaign/figures.h): no figure without a
// point, legend entries only for series with data, error bars of 1.96
// standard errors, the predicted curve, open markers for a margin below 3B,
// file names that say what a figure holds, and a PNG and an SVG of each.
#include "fss/campaign/figures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;

// A 120 x 24 crop of camera.png at `path`, so that the short codes fit its blur.
std::string write_crop(const fs::path& path) {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(120, 24, 1);
  for (int y = 0; y < crop.height; ++y) {
    for (int x = 0; x < crop.width; ++x) crop.at(0, y, x) = camera.at(0, 240 + y, 200 + x);
  }
  fs::create_directories(path.parent_path());
  const auto png = encode_png8(crop);
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

std::string write_code(const fs::path& path, const std::string& gains) {
  test::write_file(path, gains + "\n");
  return path.string();
}

// Two short codes, one with a negative gain (analog mode refuses it), in both modes.
CampaignSpec two_mode_spec(const test::TempDir& tmp) {
  CampaignSpec spec;
  spec.inputs = {write_crop(tmp / "crop.png")};
  spec.codes = {write_code(tmp / "short.txt", "1 0 1 1 0 0 1 1"),
                write_code(tmp / "negative.txt", "1 -0.5 1 1 0 0 1 1")};
  spec.modes = {ShutterMode::kNumerical, ShutterMode::kAnalog};
  spec.velocity = "0.5";
  spec.snr = "50,100,200";
  spec.trials = 3;
  spec.seed = 5;
  return spec;
}

struct RunRows {
  ResolvedCampaign campaign;
  std::vector<ResultRow> rows;
};

RunRows run(const CampaignSpec& spec, const test::TempDir& tmp, const std::string& out) {
  RunRows r{resolve_campaign(spec), {}};
  r.rows = RunCampaign(r.campaign, (tmp / out).string(), {}).rows;
  return r;
}

std::vector<std::string> series_names(const MeasuredFigure& f) {
  std::vector<std::string> names;
  for (const MeasuredSeries& s : f.series) names.push_back(s.name);
  return names;
}

TEST(CampaignFigures, SeriesWithoutDataAreLeftOutAndNamed) {
  test::TempDir tmp;
  const RunRows r = run(two_mode_spec(tmp), tmp, "out");
  const std::vector<CampaignFigureData> data = campaign_figure_data(r.campaign, r.rows);
  ASSERT_EQ(data.size(), 2u);
  EXPECT_EQ(data[0].name, "rmse_vs_snr__crop__numerical");
  EXPECT_EQ(series_names(data[0].figure), (std::vector<std::string>{"short.txt", "negative.txt"}));
  EXPECT_TRUE(data[0].figure.notes.empty());
  EXPECT_EQ(data[1].name, "rmse_vs_snr__crop__analog");
  EXPECT_EQ(series_names(data[1].figure), std::vector<std::string>{"short.txt"});
  EXPECT_EQ(data[1].figure.notes, std::vector<std::string>{"no data: negative.txt (code-refused)"});
  // A code keeps its colour from figure to figure.
  EXPECT_EQ(data[1].figure.series[0].colour, data[0].figure.series[0].colour);
  EXPECT_NE(data[0].figure.series[1].colour, data[0].figure.series[0].colour);
  // The analog figure's legend has no entry for the refused code; its note says why.
  const std::vector<CampaignFigure> figures = campaign_figures(r.campaign, r.rows);
  ASSERT_EQ(figures.size(), 2u);
  EXPECT_EQ(figures[1].svg.find(">negative.txt<"), std::string::npos);
  EXPECT_NE(figures[1].svg.find(">no data: negative.txt (code-refused)<"), std::string::npos);
  EXPECT_NE(figures[0].svg.find(">negative.txt<"), std::string::npos);
}

TEST(CampaignFigures, NoFigureWithoutAPoint) {
  test::TempDir tmp;
  CampaignSpec spec = two_mode_spec(tmp);
  spec.codes = {spec.codes[1]};  // the code analog mode refuses, alone
  const RunRows r = run(spec, tmp, "out");
  const std::vector<CampaignFigure> figures = campaign_figures(r.campaign, r.rows);
  ASSERT_EQ(figures.size(), 1u);
  EXPECT_EQ(figures[0].name, "rmse_vs_snr__crop__numerical");
}

// Each point: the mean RMSE with a bar of 1.96 sd / sqrt(trials), the prediction beside it,
// an open marker when the margin is below 3B.
TEST(CampaignFigures, PointsCarryTheirStandardErrorsAndPrediction) {
  test::TempDir tmp;
  CampaignSpec spec = two_mode_spec(tmp);
  spec.modes = {ShutterMode::kNumerical};
  spec.rmse_margin_columns = 2;  // below 3B for both codes
  const RunRows narrow = run(spec, tmp, "narrow");
  const CampaignFigureData data = campaign_figure_data(narrow.campaign, narrow.rows).at(0);
  const auto cell = [&](std::size_t row, const char* column) {
    return std::stod(narrow.rows[row][campaign_column_index(column)]);
  };
  const MeasuredSeries& s = data.figure.series.at(0);  // short.txt: the first 3 rows
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_EQ(s.measured[j], cell(j, "rmse_mean"));
    EXPECT_DOUBLE_EQ(s.error[j], 1.96 * cell(j, "rmse_sd") / std::sqrt(3.0));
    EXPECT_EQ(s.predicted[j], cell(j, "predicted_rmse"));
    EXPECT_TRUE(s.open[j]);
  }
  EXPECT_EQ(data.figure.open_key, "RMSE margin < 3B");
  EXPECT_NE(data.title.find("margin 2"), std::string::npos);
  // The paper's margin, 3B: filled markers; one trial: no bar.
  spec.rmse_margin_columns = kRmseMarginDefault;
  spec.trials = 1;
  const RunRows wide = run(spec, tmp, "wide");
  const MeasuredFigure f = campaign_figure_data(wide.campaign, wide.rows).at(0).figure;
  for (const MeasuredSeries& series : f.series) {
    EXPECT_TRUE(std::none_of(series.open.begin(), series.open.end(), [](bool b) { return b; }));
    EXPECT_TRUE(std::none_of(series.error.begin(), series.error.end(),
                             [](double e) { return std::isfinite(e); }));
  }
  EXPECT_EQ(f.points_key, "measured: mean (1 trial)");
}

TEST(CampaignFigures, NamesSayWhatTheyHoldAndAreUnique) {
  test::TempDir tmp;
  CampaignSpec spec = two_mode_spec(tmp);
  spec.modes = {ShutterMode::kNumerical};
  // Two images of one name in two folders, and a name with characters a file name avoids.
  spec.inputs = {write_crop(tmp / "a" / "crop.png"), write_crop(tmp / "b" / "crop.png"),
                 write_crop(tmp / "my image (1) é.png")};
  spec.velocity = "0.5,1";
  spec.trials = 1;
  const RunRows r = run(spec, tmp, "out");
  std::set<std::string> names;
  for (const CampaignFigureData& d : campaign_figure_data(r.campaign, r.rows)) {
    EXPECT_TRUE(names.insert(d.name).second) << d.name;
    EXPECT_LE(d.name.size(), 170u);
    EXPECT_TRUE(std::all_of(d.name.begin(), d.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    })) << d.name;
  }
  EXPECT_EQ(names.size(), 3u * (3 + 2));  // per image: a figure per snr (3) and per velocity (2)
  for (const char* name :
       {"rmse_vs_velocity__crop__numerical__snr50", "rmse_vs_velocity__crop__numerical__snr50_2",
        "rmse_vs_snr__crop__numerical__v1_2", "rmse_vs_snr__my-image-1__numerical__v0.5"}) {
    EXPECT_EQ(names.count(name), 1u) << name;
  }
}

}  // namespace
}  // namespace fss
