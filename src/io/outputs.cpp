#include "fss/io/outputs.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

#include "fss/core/error.h"
#include "fss/core/parallel.h"
#include "fss/pipeline/geometry.h"
#include "io/run_file_sources.h"

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

void write_run(const std::filesystem::path& outdir, const SimulationReport& report,
               ObservedSource observed, const Image& input, const std::string& input_path,
               const OutputOptions& options) {
  if (outdir.empty()) throw_usage_error("the output directory must not be an empty path");
  const std::vector<RunFile> files = files_to_write(options);
  const std::vector<std::string> names = output_file_names(options);
  const RunFileSources sources{report,
                               input,
                               input_path,
                               observed,
                               options.rendered_plots,
                               options.plots_in_progress,
                               names,
                               options.image_depth};
  // Each file is made as it is staged, on the report's threads, each taking
  // the next file: the four image files cost nearly all of it and come first,
  // so fixed blocks would give them all to one thread; and a file's bytes are
  // freed once written, so the large ones are not all in memory at once.
  std::vector<OutputFile> staged;
  staged.reserve(files.size());
  for (const RunFile& file : files) {
    staged.push_back({file.name, {}, [&sources, make = file.make] { return make(sources); }});
  }
  std::vector<std::string> inputs = options.other_inputs;
  inputs.insert(inputs.begin(), input_path);
  std::vector<std::string> every_name;  // a file of the old set this run does not write goes
  for (const RunFile& file : run_files()) every_name.emplace_back(file.name);
  write_output_set(outdir, staged, inputs, every_name, report.options.threads);
}

}  // namespace

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

void check_outputs_memory(const SimulationOptions& simulation, const Image& input,
                          const ShutterCode& code, const OutputOptions& options,
                          const ObservedRowSink* observed_sink) {
  const std::size_t extra = output_encoding_bytes_per_sample(options, input.channels);
  if (simulation.max_memory_bytes == 0 || extra == 0 || !simulation.IsValid(nullptr)) return;
  const double v = simulation.velocity_px_per_slot;
  const double v_r = simulation.restore_velocity_px_per_slot.value_or(v);
  const double speed = std::max(std::abs(v), std::abs(v_r));
  if (!too_narrow_reason(input.width, code.length(), speed, simulation.dt,
                         simulation.rmse_margin_columns)
           .empty()) {
    return;
  }
  const Geometry geometry = Geometry::compute(input.width, code.length(), speed, simulation.dt);
  const std::size_t needed =
      estimate_working_memory_bytes(input.width, input.height, input.channels, geometry, simulation,
                                    code.length(), observed_sink, extra);
  if (needed > simulation.max_memory_bytes) {
    throw_memory_limit_error("a run on this " + std::to_string(input.width) + " x " +
                                 std::to_string(input.height) + " x " +
                                 std::to_string(input.channels) +
                                 " image with its extra outputs (sheet, report, float or 16-bit)",
                             needed, simulation.max_memory_bytes);
  }
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
  write_run(outdir, report, std::cref(report.observed), input, input_path, options);
}

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const ObservedPng8& observed, const Image& input, const std::string& input_path,
                   const OutputOptions& options) {
  write_run(outdir, report, std::cref(observed), input, input_path, options);
}

}  // namespace fss
