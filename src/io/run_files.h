// The files a run writes, as one table: which files there are, what each
// holds, when it is written and how it is made. The table drives
// write_outputs (which files, in which order), output_file_names,
// report.html's figures and list of files, and a test holds the "Outputs"
// table of docs/cli.md to it. Adding an output is adding a row (src/io/run_files.cpp).
// report.json lists no files.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace fss {

// When a file of a run is written.
enum class RunFileCondition {
  kAlways,
  kPlots,       // OutputOptions::plots (fssim: unless --no-plots)
  kSheet,       // OutputOptions::sheet (fssim --sheet)
  kHtmlReport,  // OutputOptions::html_report (fssim --report)
  kFloat,       // OutputOptions::float_outputs (fssim --save-float)
};

// How report.html shows a file besides linking it.
enum class RunFileFigure {
  kNone,
  kImage,  // among the images, at the size of the output crop
  kPlot,   // among the plots, at kPlotWidth x kPlotHeight (plot.h)
};

// What the files of a run are made from (defined in src/io).
struct RunFileSources;

struct FrameColour {
  std::uint8_t red = 0, green = 0, blue = 0;
};

struct RunFile {
  const char* name;
  RunFileCondition when;
  const char* content;  // what it holds, as report.html's list of files says
  // Makes the file's bytes.
  std::string (*make)(const RunFileSources& sources) = nullptr;
  RunFileFigure figure = RunFileFigure::kNone;
  // For a figure: its caption on report.html and the colour of the frame
  // drawn around it there (report_figures, html_report.h).
  const char* caption = "";
  FrameColour frame = {};
  // Made before the files of a lower rank (OutputFile::rank).
  int rank = 0;
};

// Every file a run may write, in the order write_outputs writes them.
std::span<const RunFile> run_files();

}  // namespace fss
