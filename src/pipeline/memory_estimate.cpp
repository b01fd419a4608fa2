#include "fss/pipeline/memory_estimate.h"

#include <algorithm>
#include <cstddef>

#include "core/huge_pages.h"
#include "fss/core/error.h"
#include "model/aggregated_sampler.h"
#include "pipeline/fitted_restoration.h"
#include "pipeline/row_pipeline.h"
#include "pipeline/run_checks.h"

namespace fss {

namespace {

// The input, the observed (doubles, or 8-bit samples when `!keep_observed`) and restored outputs
// (one more restoration buffer when trials > 1), and the larger of the RMSE_CI scratch and the
// PNG encoding buffers. Rows in flight are a few kilobytes a thread and are not counted, nor are
// the exact prediction's variance sums (at most 64 rows of W - B doubles, docs/method.md §6b).
std::size_t working_bytes(int width, int height, int channels, const Geometry& geometry, int trials,
                          bool keep_observed, std::size_t extra_encoding_bytes_per_sample) {
  const auto w = static_cast<std::size_t>(width);
  const auto h = static_cast<std::size_t>(height);
  const auto c = static_cast<std::size_t>(channels);
  const auto wo = static_cast<std::size_t>(std::max(geometry.output_width, 0));
  const auto ci_width =
      static_cast<std::size_t>(std::max(geometry.output_width - 2 * geometry.blur_length, 0));
  const std::size_t input = w * h * c * sizeof(double);
  const std::size_t outputs =
      ((trials > 1 ? 2 : 1) * sizeof(double) + (keep_observed ? sizeof(double) : 1)) * wo * h * c;
  // RMSE_CI (metrics.h): 16 bytes and at most 1 bit a pixel of one
  // channel's window (its records, a's group starts), and buffers of a
  // bounded size: two threads' level counts (1 MiB) and sorters (a huge
  // page each: 4 MiB), the groups of an 8- or 16-bit ground truth (at most
  // 65536: 1.25 MiB with their values and starts), b's tied runs (512 KiB),
  // the 16-bit levels (512 KiB): 7.25 MiB, 7.75 with the allocator's.
  const std::size_t ci_pixels = ci_width * h;
  const std::size_t midway = 16 * ci_pixels + ci_pixels / 8 + (std::size_t{31} << 18);
  // The four image PNGs, each at most a byte a sample (ISA-L stores what it
  // cannot compress), encoded row by row straight into their files' bytes:
  // no raster of samples, no copy (src/io/png_write.cpp); and the encoders'
  // own buffers, for each PNG encoded at once, at most five: ISA-L's state
  // (82 KiB) and, on whole huge pages, its level buffer (276 KiB), a chunk of
  // stream and a block of rows (256 KiB and a row), and three rows (16-bit samples at most).
  const std::size_t rows = 4 * 2 * w * c;
  const std::size_t huge = detail::kHugePageBytes;
  const std::size_t encoder_pages = ((std::size_t{800} << 10) + rows + huge - 1) / huge * huge;
  const std::size_t encoders = 5 * (encoder_pages + (std::size_t{128} << 10));
  // Each file's bytes are advised onto huge pages (reserve_on_huge_pages): up to a huge page
  // past what it writes, for each of the five.
  const std::size_t encoding =
      (4 + extra_encoding_bytes_per_sample) * wo * h * c + encoders + 5 * huge;
  // Buffers of 1 MiB or more are mapped in whole huge pages (core/huge_pages.cpp): up to 2 MiB
  // more each for the input, the outputs and the records.
  const std::size_t rounding = detail::kHugePageBytes * (1 + (trials > 1 ? 2 : 1) + 1 + 1);
  return kBaselineMemoryBytes + input + outputs + std::max(midway, encoding) + rounding;
}

// Under a velocity distribution (docs/method.md §13), one velocity's kernel part beside the
// plan at a time (a trial's, or a velocity's of the prediction): the observer's filters (a
// complex half spectrum per slot), the restorer's (at most the inverse filter's N / 2 + 1 bins
// and the folded convolution's two filters of at most 2 (Wa + Wo) bins), W(j) and the impulse
// response it is made from, and the noise-free pass's sums (64 blocks of Wa and one per row).
std::size_t velocity_kernel_bytes(int width, int height, int channels, const Geometry& geometry,
                                  const SimulationOptions& options, int code_length) {
  if (!options.velocity_distribution) return 0;
  const auto bins = static_cast<std::size_t>(width) / 2 + 1;
  const std::size_t slots =
      options.mode == ShutterMode::kAnalog ? 1 : static_cast<std::size_t>(std::max(code_length, 1));
  const auto wa = static_cast<std::size_t>(std::max(geometry.observed_width, 0));
  const auto wo = static_cast<std::size_t>(std::max(geometry.output_width, 0));
  const std::size_t complex_bytes = 16;
  const std::size_t restorer = complex_bytes * ((wa + 1) + 4 * (wa + wo));
  const std::size_t weights = sizeof(double) * 3 * wa;
  const std::size_t rows = static_cast<std::size_t>(height) * static_cast<std::size_t>(channels);
  const std::size_t pass = sizeof(double) * (64 * wa + rows);
  return complex_bytes * slots * bins + restorer + weights + pass;
}

}  // namespace

std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry, int trials,
                                          const ObservedRowSink* observed_sink,
                                          std::size_t extra_encoding_bytes_per_sample) {
  return working_bytes(width, height, channels, geometry, trials, observed_sink == nullptr,
                       extra_encoding_bytes_per_sample);
}

// RowPipeline::plan_bytes: aggregated noise with trials > 1 keeps each row's recorded plan (M, V,
// its Knuth-branch pixels and its groups' Lambda) for the later trials; a code of L gains has at
// most L / 2 groups.
std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry,
                                          const SimulationOptions& options, int code_length,
                                          const ObservedRowSink* observed_sink,
                                          std::size_t extra_encoding_bytes_per_sample) {
  return working_bytes(width, height, channels, geometry, options.trials, observed_sink == nullptr,
                       extra_encoding_bytes_per_sample) +
         RowPipeline::plan_bytes(width, height, channels, options, code_length, code_length / 2) +
         fitted_restoration_bytes(options, geometry.observed_width, height, channels) +
         velocity_kernel_bytes(width, height, channels, geometry, options, code_length);
}

std::size_t estimate_run_memory_bytes(const ImageShape& shape, const SimulationOptions& options,
                                      const ShutterCode& code, bool observed_to_sink,
                                      std::size_t extra_encoding_bytes_per_sample) {
  // The run's geometry: its blur covers both velocities (under a distribution, its support).
  const Geometry geometry = checked_geometry(options, shape.width, code);
  return working_bytes(shape.width, shape.height, shape.channels, geometry, options.trials,
                       !observed_to_sink, extra_encoding_bytes_per_sample) +
         RowPipeline::plan_bytes(shape.width, shape.height, shape.channels, options, code.length(),
                                 gain_group_count(code.gains)) +
         fitted_restoration_bytes(options, geometry.observed_width, shape.height, shape.channels) +
         velocity_kernel_bytes(shape.width, shape.height, shape.channels, geometry, options,
                               code.length());
}

void check_run_memory(const ImageShape& shape, const SimulationOptions& options,
                      const ShutterCode& code, bool observed_to_sink,
                      std::size_t extra_encoding_bytes_per_sample, const std::string& subject) {
  if (options.max_memory_bytes == 0) return;
  const std::size_t needed = estimate_run_memory_bytes(shape, options, code, observed_to_sink,
                                                       extra_encoding_bytes_per_sample);
  if (needed > options.max_memory_bytes) {
    throw_memory_limit_error(subject, needed, options.max_memory_bytes);
  }
}

}  // namespace fss
