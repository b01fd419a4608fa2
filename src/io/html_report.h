// report.html: one page with what the paper's online demo shows for a run —
// the parameters, the measured and predicted errors, the observed, restored,
// ground-truth and residual images side by side at the same scale, and the
// plots of the code and of |K|. The page is self-contained: it refers to the
// run's other output files by relative names and to nothing else (no
// scripts, no network). Every string that comes from the user is escaped.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fss/pipeline/simulate.h"

namespace fss {

// A picture of the page and the colour of the frame drawn around it, so that
// it can be told apart from the others on a rendered page (the figure
// columns of run_files.h).
struct ReportFigure {
  const char* file;
  const char* caption;
  std::uint8_t red, green, blue;
};

// Width in CSS pixels of the frames.
inline constexpr int kReportFrameWidth = 3;

// The four images, then the two plots, in page order.
const std::vector<ReportFigure>& report_figures();

// The page for `report`, whose input was `input_path`. `output_files` are the
// names of the files written next to it: the page shows the figures among
// them, links every one of them (with what it holds, from run_files.h), and
// refers to no other file.
std::string html_report(const SimulationReport& report, const std::string& input_path,
                        const std::vector<std::string>& output_files);

// `text` with & < > " ' replaced by character references, and bytes that are
// not valid UTF-8 (and control characters) by U+FFFD.
std::string html_escape(std::string_view text);

}  // namespace fss
