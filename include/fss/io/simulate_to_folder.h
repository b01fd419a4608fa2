// A whole run from an image file into an output folder: what `fssim --input` does, for every
// interface (the command line, Python, a library user).
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "fss/io/outputs.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss {

struct FolderRunOptions {
  OutputOptions outputs;
  // 16-bit image PNGs for an input of more than 8 bits a sample, 8-bit otherwise
  // (`--png-depth auto`); when false, outputs.image_depth.
  bool image_depth_from_input = false;
  // Called before each stage with what the run does next ("reading input 'camera.png'"), for a
  // caller that puts it in its error messages. May be empty.
  std::function<void(const std::string&)> on_stage;
  // Called with the report once the simulation is done, before the outputs are written. May be
  // empty.
  std::function<void(const SimulationReport&)> on_simulated;
};

// Reads the image at `input_path` (PNG or TIFF, image_io.h), simulates `code` on it and writes
// the outputs into `outdir`: the report and the files of Simulate and write_outputs (all of them
// or none), byte for byte. A run over options.max_memory_bytes is refused from the PNG header,
// before decoding. The code file `code` was read from, if any, belongs in outputs.other_inputs, so
// that it is never overwritten; the file of a discrete options.velocity_distribution is never
// overwritten either.
SimulationReport SimulateToFolder(const std::string& input_path, const ShutterCode& code,
                                  const std::filesystem::path& outdir,
                                  const SimulationOptions& options,
                                  const FolderRunOptions& run = {});

}  // namespace fss
