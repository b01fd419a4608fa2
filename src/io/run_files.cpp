#include "io/run_files.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/io/tiff_io.h"
#include "fss/model/code.h"
#include "fss/pipeline/metrics.h"
#include "io/html_report.h"
#include "io/png_write.h"
#include "io/run_file_sources.h"
#include "io/run_text.h"
#include "io/sheet.h"

namespace fss {

namespace {

std::string as_string(const std::vector<std::uint8_t>& bytes) {
  return {bytes.begin(), bytes.end()};
}

std::string encode_observed(const Image& kept, const SimulationReport& /*report*/, PngDepth depth) {
  if (kept.data.empty()) {
    throw_usage_error(
        "observed.png: the report keeps no observed image (Simulate ran with an ObservedRowSink) "
        "and no "
        "ObservedPng8 was given to write_outputs");
  }
  return detail::encode_png_string(kept, depth);
}

std::string encode_observed(const ObservedPng8& rows, const SimulationReport& r, PngDepth depth) {
  const Image& outputs = r.restored;
  if (rows.width() != outputs.width || rows.height() != outputs.height ||
      rows.channels() != outputs.channels) {
    throw_usage_error("observed.png: the ObservedPng8 given to write_outputs holds a " +
                      std::to_string(rows.width()) + " x " + std::to_string(rows.height()) + " x " +
                      std::to_string(rows.channels()) + " image, the report's outputs are " +
                      std::to_string(outputs.width) + " x " + std::to_string(outputs.height) +
                      " x " + std::to_string(outputs.channels));
  }
  if (depth != PngDepth::k8) {
    throw_usage_error(
        "observed.png: 16-bit outputs need the report's observed image; an ObservedPng8 holds "
        "8-bit samples");
  }
  return rows.encode_string();
}

std::string make_observed(const RunFileSources& s) {
  return std::visit(
      [&](const auto& source) { return encode_observed(source.get(), s.report, s.image_depth); },
      s.observed);
}

// The images are encoded straight into the file's bytes (no copy).
std::string make_restored(const RunFileSources& s) {
  return detail::encode_png_string(s.report.restored, s.image_depth);
}

// The ground truth and the residual are encoded straight from the input and
// the restoration, row by row.
std::string make_groundtruth(const RunFileSources& s) {
  const int offset = s.report.output_first_column(), wo = s.report.restored.width;
  const Image& input = s.input;
  return detail::encode_png_string(
      wo, input.height, input.channels,
      [&](int c, int y, double* row) {
        std::copy(input.row(c, y) + offset, input.row(c, y) + offset + wo, row);
      },
      s.image_depth);
}

// groundtruth - restored, stretched affinely to [0, 255] (docs/method.md §5).
std::string make_residual(const RunFileSources& s) {
  const int offset = s.report.output_first_column(), wo = s.report.restored.width;
  const Image& input = s.input;
  const Image& restored = s.report.restored;
  const ResidualRange range = residual_range(input, offset, restored);
  return detail::encode_png_string(
      wo, input.height, input.channels,
      [&](int c, int y, double* row) {
        const double* truth = input.row(c, y) + offset;
        const double* restored_row = restored.row(c, y);
        for (int x = 0; x < wo; ++x) row[x] = range.stretch(truth[x] - restored_row[x]);
      },
      s.image_depth);
}

// The float TIFFs hold the values themselves: no rounding, no clamping.
std::string make_observed_tif(const RunFileSources& s) {
  const auto* kept = std::get_if<std::reference_wrapper<const Image>>(&s.observed);
  if (kept == nullptr || kept->get().data.empty()) {
    throw_usage_error(
        "observed.tif: float outputs need the report's observed image; an ObservedPng8 holds "
        "8-bit samples and Simulate kept none");
  }
  return as_string(encode_tiff_float(kept->get()));
}

std::string make_restored_tif(const RunFileSources& s) {
  return as_string(encode_tiff_float(s.report.restored));
}

// groundtruth - restored, as it is (docs/method.md §5).
std::string make_residual_tif(const RunFileSources& s) {
  const int offset = s.report.output_first_column(), wo = s.report.restored.width;
  const Image& input = s.input;
  const Image& restored = s.report.restored;
  return as_string(
      encode_tiff_float(wo, input.height, input.channels, [&](int c, int y, double* row) {
        const double* truth = input.row(c, y) + offset;
        const double* restored_row = restored.row(c, y);
        for (int x = 0; x < wo; ++x) {
          row[x] = truth[x] - restored_row[x];
        }
      }));
}

std::string make_code_txt(const RunFileSources& s) {
  return format_code_txt({s.report.code_name, s.report.gains});
}

std::string make_spectrum_txt(const RunFileSources& s) {
  const SimulationOptions& o = s.report.options;
  return format_spectrum_txt(s.report.gains, first_trial_velocity(o), o.dt);
}

std::string make_report_json(const RunFileSources& s) {
  return report_json_text(s.report, s.input_path);
}

std::string make_code_png(const RunFileSources& s) {
  return as_string(run_code_png(s.report, s.drawn_plots()));
}

std::string make_spectrum_png(const RunFileSources& s) {
  return as_string(run_spectrum_png(s.report, s.drawn_plots()));
}

std::string make_sheet(const RunFileSources& s) {
  return as_string(figure_sheet_png(s.report, s.input));
}

std::string make_html_report(const RunFileSources& s) {
  return html_report(s.report, s.input_path, s.names);
}

using enum RunFileCondition;
using enum RunFileFigure;

// The image files are made longest first (their rank), so that the threads end together:
// sheet.png when asked for (three images' pixels through PLplot and zlib); residual.png,
// whose range takes a pass over the image before it is encoded and whose noise compresses
// worst; restored.png, with the noise the inverse filter amplifies; the input's crop; and
// observed.png, smoothed by the blur, the quickest to compress (a 4000x3000 photograph with
// noise: 0.21, 0.13, 0.11 and 0.08 s for the last four).
// Every frame colour has a zero component, which neither a gray image nor
// the plots' palette (all components >= 20) can produce.
// One row a file (kept by hand: clang-format would give every field a line).
// clang-format off
constexpr std::array kRunFiles = {
    RunFile{.name = "observed.png", .when = kAlways,
            .content = "the observation divided by K(0), output crop", .make = make_observed,
            .figure = kImage, .caption = "observed (divided by K(0))", .frame = {0, 114, 178}},
    RunFile{.name = "restored.png", .when = kAlways,
            .content = "the inverse-filtered restoration, output crop", .make = make_restored,
            .figure = kImage, .caption = "restored (inverse filter)", .frame = {0, 158, 115},
            .rank = 2},
    RunFile{.name = "groundtruth.png", .when = kAlways, .content = "the input, same crop",
            .make = make_groundtruth, .figure = kImage,
            .caption = "ground truth (input, same crop)", .frame = {230, 159, 0}, .rank = 1},
    RunFile{.name = "residual.png", .when = kAlways,
            .content = "ground truth − restored, stretched to [0, 255]", .make = make_residual,
            .figure = kImage,
            .caption = "residual (ground truth − restored, stretched to [0, 255])",
            .frame = {204, 0, 122}, .rank = 3},
    RunFile{.name = "observed.tif", .when = kFloat,
            .content = "the observation divided by K(0), output crop, 32-bit float, unclamped",
            .make = make_observed_tif},
    RunFile{.name = "restored.tif", .when = kFloat,
            .content = "the restoration, output crop, 32-bit float, unclamped",
            .make = make_restored_tif},
    RunFile{.name = "residual.tif", .when = kFloat,
            .content = "ground truth − restored, 32-bit float, not stretched",
            .make = make_residual_tif},
    RunFile{.name = "code.txt", .when = kAlways, .content = "the gains, reference format",
            .make = make_code_txt},
    RunFile{.name = "spectrum.txt", .when = kAlways,
            .content = "|K(ξ)| at 100 frequencies, reference format", .make = make_spectrum_txt},
    RunFile{.name = "report.json", .when = kAlways, .content = "every parameter and result",
            .make = make_report_json},
    RunFile{.name = "code.png", .when = kPlots, .content = "plot of the gain function",
            .make = make_code_png, .figure = kPlot, .caption = "gain function α(t)",
            .frame = {120, 0, 200}},
    RunFile{.name = "spectrum.png", .when = kPlots,
            .content = "plot of |K(ξ)| against the snapshot's", .make = make_spectrum_png,
            .figure = kPlot, .caption = "|K(ξ)|, the snapshot's dashed", .frame = {160, 130, 0}},
    RunFile{.name = "sheet.png", .when = kSheet,
            .content = "observed | restored | residual in one picture", .make = make_sheet,
            .rank = 4},
    RunFile{.name = "report.html", .when = kHtmlReport, .content = "this page",
            .make = make_html_report},
};
// clang-format on

}  // namespace

std::span<const RunFile> run_files() { return kRunFiles; }

}  // namespace fss
