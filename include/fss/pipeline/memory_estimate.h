// The estimated peak memory of a run, and the one check of it against
// SimulationOptions::max_memory_bytes that every interface makes.
#pragma once

#include <cstddef>
#include <string>

#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/simulation_options.h"

namespace fss {

// Memory of the process before any image (code, libraries, stacks), counted in every estimate.
inline constexpr std::size_t kBaselineMemoryBytes = std::size_t{32} << 20;

// Estimated peak memory of Simulate plus write_outputs, in bytes: the input image, the outputs
// (the observed one as 8-bit samples when its rows go to an `observed_sink`), the larger of the
// RMSE_CI scratch and the PNG encoding buffers, and kBaselineMemoryBytes.
// `extra_encoding_bytes_per_sample`: bytes a sample of the output crop that the outputs beyond
// the default ones add (outputs.h: output_encoding_bytes_per_sample).
std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry, int trials,
                                          const ObservedRowSink* observed_sink = nullptr,
                                          std::size_t extra_encoding_bytes_per_sample = 0);

// The same for a run of `options` with a code of `code_length` gains, its noise model's memory
// included: the estimate Simulate checks options.max_memory_bytes against.
std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry,
                                          const SimulationOptions& options, int code_length,
                                          const ObservedRowSink* observed_sink = nullptr,
                                          std::size_t extra_encoding_bytes_per_sample = 0);

// The size of an image a run is checked for before it exists (from a PNG
// header or an array's shape).
struct ImageShape {
  int width = 0;
  int height = 0;
  int channels = 0;
};

// The estimate for a run of `options` and `code` on an image of `shape`, the observed rows kept
// as 8-bit samples when `observed_to_sink`. Throws the usage fss::Error Simulate would when the
// run cannot be made (options, code, an image too narrow).
std::size_t estimate_run_memory_bytes(const ImageShape& shape, const SimulationOptions& options,
                                      const ShutterCode& code, bool observed_to_sink,
                                      std::size_t extra_encoding_bytes_per_sample = 0);

// Throws the kLimit fss::Error "<subject> needs about N of memory, more than the memory limit of
// M" when estimate_run_memory_bytes exceeds options.max_memory_bytes (0: no limit). `subject`
// names the run ("a run on this 512 x 512 x 1 image").
void check_run_memory(const ImageShape& shape, const SimulationOptions& options,
                      const ShutterCode& code, bool observed_to_sink,
                      std::size_t extra_encoding_bytes_per_sample, const std::string& subject);

}  // namespace fss
