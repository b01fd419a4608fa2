#include "fss/io/outputs.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

#include "core/parallel.h"
#include "fss/core/error.h"
#include "fss/pipeline/geometry.h"
#include "io/output_set.h"
#include "io/run_file_sources.h"
#include "io/write_run.h"

namespace fss {

namespace {

// The rows of run_files() written under `options`, in order.
std::vector<RunFile> files_to_write(const OutputOptions& options) {
  std::vector<RunFile> files;
  for (const RunFile& file : run_files()) {
    if (is_written(file.when, options)) files.push_back(file);
  }
  return files;
}

// All files are staged and renamed into place only once every one of them has been written
// (write_output_set); on failure whatever was staged is removed. The ground truth and the
// residual are encoded from `input` row by row.
void write_run(const std::filesystem::path& outdir, const SimulationReport& report,
               ObservedSource observed, const Image& input, const std::string& input_path,
               const OutputOptions& options, const PlotsAhead& plots) {
  if (outdir.empty()) throw_usage_error("the output directory must not be an empty path");
  const std::vector<RunFile> files = files_to_write(options);
  const std::vector<std::string> names = output_file_names(options);
  const RunFileSources sources{report,      input,
                               input_path,  observed,
                               plots.drawn, plots.in_progress,
                               names,       options.image_depth};
  // Each file is made as it is staged, on the report's threads, each taking the next file:
  // the four image files cost nearly all of it and come first, longest first (RunFile::rank),
  // so fixed blocks would give them all to one thread; and a file's bytes are freed once
  // written, so the large ones are not all in memory at once.
  std::vector<OutputFile> staged;
  staged.reserve(files.size());
  for (const RunFile& file : files) {
    staged.push_back(
        {file.name, {}, [&sources, make = file.make] { return make(sources); }, file.rank});
  }
  std::vector<std::string> inputs = options.other_inputs;
  inputs.insert(inputs.begin(), input_path);
  std::vector<std::string> every_name;  // a file of the old set this run does not write goes
  for (const RunFile& file : run_files()) every_name.emplace_back(file.name);
  write_output_set(outdir, staged, inputs, every_name, report.options.threads);
}

}  // namespace

// 16-bit PNGs double the 4 bytes of the four image PNGs; each float TIFF holds 4 and is copied
// once into its output file; sheet.png and report.html as below.
std::size_t output_encoding_bytes_per_sample(const OutputOptions& options, int channels) {
  std::size_t bytes = 0;
  if (options.image_depth == PngDepth::k16) bytes += 4;  // two bytes a sample, not one
  if (options.float_outputs) bytes += 3 * 2 * sizeof(float);
  if (options.sheet) {
    // The ground truth crop and the residual as doubles (8 + 8), the RGBA
    // picture of three panels (12 bytes a pixel), its samples and their PNG
    // (3 + 3 at most).
    bytes += 8 + 8 +
             (12 + static_cast<std::size_t>(std::max(channels, 1)) - 1) /
                 static_cast<std::size_t>(std::max(channels, 1)) +
             3 + 3;
  }
  // report.html: the PNGs of the page in base64 and the page itself.
  if (options.html_report) bytes += 8;
  return bytes;
}

bool is_written(RunFileCondition when, const OutputOptions& options) {
  switch (when) {
    case RunFileCondition::kAlways:
      return true;
    case RunFileCondition::kPlots:
      return options.plots;
    case RunFileCondition::kSheet:
      return options.sheet;
    case RunFileCondition::kHtmlReport:
      return options.html_report;
    case RunFileCondition::kFloat:
      return options.float_outputs;
  }
  return false;
}

std::vector<std::string> output_file_names(const OutputOptions& options) {
  std::vector<std::string> names;
  for (const RunFile& file : files_to_write(options)) names.emplace_back(file.name);
  return names;
}

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options) {
  write_run(outdir, report, std::cref(report.observed), input, input_path, options, {});
}

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path, const OutputOptions& options,
                   const PlotsAhead& plots) {
  write_run(outdir, report, std::cref(report.observed), input, input_path, options, plots);
}

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const ObservedPng8& observed, const Image& input, const std::string& input_path,
                   const OutputOptions& options, const PlotsAhead& plots) {
  write_run(outdir, report, std::cref(observed), input, input_path, options, plots);
}

}  // namespace fss
