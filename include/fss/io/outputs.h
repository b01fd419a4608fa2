// Writing a run's outputs (the files of run_files.h): all files are staged
// and renamed into place only once every one of them has been written, so a
// failed run leaves nothing.
#pragma once

#include <filesystem>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/observed_png8.h"
#include "fss/io/output_set.h"
#include "fss/io/png_io.h"
#include "fss/io/run_files.h"
#include "fss/io/run_plots.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// Optional outputs of a run.
struct OutputOptions {
  bool plots = true;         // code.png and spectrum.png (plot.h)
  bool sheet = false;        // sheet.png: observed | restored | residual (sheet.h)
  bool html_report = false;  // report.html (html_report.h)
  // observed.tif, restored.tif and residual.tif: 32-bit float, unclamped
  // (tiff_io.h). They need the report's observed image, not an ObservedPng8.
  bool float_outputs = false;
  // Bits a sample of observed.png, restored.png, groundtruth.png and
  // residual.png (png_io.h: png8_sample, png16_sample); the plots and
  // sheet.png stay 8-bit. 16 bits need the report's observed image.
  PngDepth image_depth = PngDepth::k8;
  // Files besides the input image that must never be overwritten (the code file).
  std::vector<std::string> other_inputs;
  // code.png and spectrum.png drawn ahead (render_run_plots) for the
  // report's code and motion, used instead of drawing them again; a usage
  // error if they were drawn for another run. Empty: write_outputs draws them.
  std::optional<RunPlots> rendered_plots;
  // code.png and spectrum.png being drawn on another thread (render_run_plots),
  // when rendered_plots is empty: the files that show them wait for them, the
  // others are made meanwhile. Not valid: write_outputs draws them.
  std::shared_future<RunPlots> plots_in_progress;
};

// Bytes a sample of the output crop that the outputs `options` asks for take
// while they are made, beyond the default ones (estimate_working_memory_bytes,
// simulate.h): 16-bit PNGs double the 4 of the four image PNGs; each float
// TIFF holds 4 and is copied once into its output file; sheet.png holds the
// ground truth and the residual (8 + 8), an RGBA picture (12 / channels),
// its samples and their PNG (3 + 3); report.html 8 (the page's PNGs in
// base64, copied).
std::size_t output_encoding_bytes_per_sample(const OutputOptions& options, int channels = 1);

// Throws the kLimit error Simulate throws, with the memory of the outputs
// `options` asks for counted as well (output_encoding_bytes_per_sample, and
// the observed image kept as doubles when `observed_sink` is null). Does
// nothing when options.max_memory_bytes is 0 or when Simulate would refuse
// the run for another reason (it says why then).
void check_outputs_memory(const SimulationOptions& simulation, const Image& input,
                          const ShutterCode& code, const OutputOptions& options,
                          const ObservedRowSink* observed_sink);

// Whether a file written `when` is written under `options`.
bool is_written(RunFileCondition when, const OutputOptions& options);

// Names of the files write_outputs creates, in the order of run_files().
std::vector<std::string> output_file_names(const OutputOptions& options = {});

// Writes the files of run_files() that `options` asks for into `outdir`
// (created if missing): by default observed.png, restored.png,
// groundtruth.png, residual.png, code.txt, spectrum.txt, report.json,
// code.png and spectrum.png. `input` is the image the report was made from
// (the ground truth and the residual are encoded from it row by row).
// observed.png is the report's observed image, which it must then keep.
// Refuses, before writing anything, to replace `input_path` or any of
// `options.other_inputs` (such as the code file) or to write into a path
// that is not a directory (write_output_set). The files are published as one
// set: a file of run_files() this run does not write (sheet.png of an
// earlier --sheet run) goes with the old set. Throws a runtime fss::Error on
// failure (a usage one for an empty `outdir`), after removing whatever it
// staged: existing files are never touched then.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options = {});

// The same with observed.png made from the rows `observed` collected during
// the run (which then need not keep its observed image): it must hold every
// row, at the size of the report's outputs. sheet.png needs the kept image.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const ObservedPng8& observed, const Image& input, const std::string& input_path,
                   const OutputOptions& options = {});

}  // namespace fss
