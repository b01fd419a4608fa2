// Writing a run's output files into a folder, published as one set: a failed run leaves
// nothing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// Optional outputs of a run.
struct OutputOptions {
  bool plots = true;         // code.png and spectrum.png (plot.h)
  bool sheet = false;        // sheet.png: observed | restored | residual
  bool html_report = false;  // report.html
  // observed.tif, restored.tif and residual.tif: 32-bit float, unclamped (tiff_io.h); they need
  // the report's observed image.
  bool float_outputs = false;
  // Bits a sample of observed.png, restored.png, groundtruth.png and residual.png (png_io.h:
  // png8_sample, png16_sample); the plots and sheet.png stay 8-bit. 16 bits need the report's
  // observed image.
  PngDepth image_depth = PngDepth::k8;
  // Files besides the input image that must never be overwritten (the code file).
  std::vector<std::string> other_inputs;
};

// Bytes a sample of the output crop that the outputs `options` asks for take while they are
// made, beyond the default ones (estimate_working_memory_bytes, memory_estimate.h).
std::size_t output_encoding_bytes_per_sample(const OutputOptions& options, int channels = 1);

// Names of the files write_outputs creates under `options`, in the order it lists them.
std::vector<std::string> output_file_names(const OutputOptions& options = {});

// Writes the files `options` asks for (output_file_names) into `outdir`, created if missing.
// `input` is the image the report was made from; the report must keep its observed image. Refuses,
// before writing anything, to replace `input_path` or any of `options.other_inputs` or to write
// into a path that is not a directory. Published as one set: a file of an earlier run that this
// one does not write (sheet.png) goes with the old set. Throws a runtime fss::Error on failure (a
// usage one for an empty `outdir`), leaving existing files untouched.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options = {});

}  // namespace fss
