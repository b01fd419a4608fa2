#include "fss/io/simulate_to_folder.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <future>
#include <optional>
#include <system_error>

#include "core/parallel.h"
#include "fss/core/error.h"
#include "fss/io/image_io.h"
#include "fss/io/png_io.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/memory_estimate.h"
#include "io/observed_png8.h"
#include "io/run_plots.h"
#include "io/write_run.h"

namespace fss {

namespace {

// Runs `check`, letting a usage error go: Simulate reports those, in its own
// order.
template <typename Check>
void unless_simulate_refuses(const Check& check) {
  try {
    check();
  } catch (const Error& error) {
    if (error.kind() != ErrorKind::kUsage) throw;
  }
}

bool several_threads(const SimulationOptions& options) {
  return options.IsValid(nullptr) && resolve_thread_count(options.threads) > 1;
}

// code.png and spectrum.png need only the code and the motion: drawn on
// their own thread while the image is read and simulated. Not without a
// second thread (write_outputs draws them then), nor for a run Simulate
// will refuse: its error should not wait for them.
std::shared_future<RunPlots> start_plots(const ShutterCode& code, const SimulationOptions& options,
                                         bool plots) {
  if (!plots || !several_threads(options)) return {};
  try {
    check_code_for_mode(code, options.mode);
    return std::async(std::launch::async, render_run_plots, code, options).share();
  } catch (const Error&) {
    // Simulate reports it
  } catch (const std::system_error&) {
    // no thread: drawn by write_outputs
  }
  return {};
}

// The simulation plan made on its own thread while the image is decoded,
// for a PNG whose header gives the width. Empty without a header, a second
// thread or a plan: Simulate then makes the plan itself, and reports any
// error in its own order.
using EarlyPlan = std::future<std::optional<SimulationPlan>>;
EarlyPlan start_plan(const std::optional<PngHeaderSize>& size, const SimulationOptions& options,
                     const ShutterCode& code) {
  if (!size || size->width > kMaxImageSide || size->height > kMaxImageSide ||
      !several_threads(options)) {
    return {};
  }
  const auto make = [options, code, width = size->width]() -> std::optional<SimulationPlan> {
    try {
      return SimulationPlan(options, width, code);
    } catch (const Error&) {
      return std::nullopt;  // Simulate reports it
    }
  };
  try {
    return std::async(std::launch::async, make);
  } catch (const std::system_error&) {
    return {};  // no thread: Simulate makes the plan
  }
}

// The size a PNG's header declares, when the file can hold it: a header
// declaring more pixels (at 1 bit each) than the file can hold after
// deflate (at most 1032 times) is corrupt, and read_png says so. Empty for
// anything else (read_image says what is wrong).
std::optional<PngHeaderSize> plausible_png_header(const std::string& input) {
  const std::optional<PngHeaderSize> size = read_png_header_size(input);
  if (!size) return std::nullopt;
  std::error_code ec;
  const std::uintmax_t file_bytes = std::filesystem::file_size(input, ec);
  if (ec || static_cast<double>(size->width) * size->height / 8.0 >
                1032.0 * (static_cast<double>(file_bytes) + 1.0)) {
    return std::nullopt;
  }
  return size;
}

PngDepth image_depth(const FolderRunOptions& run, int input_bits_per_sample) {
  if (!run.image_depth_from_input) return run.outputs.image_depth;
  return input_bits_per_sample > 8 ? PngDepth::k16 : PngDepth::k8;
}

// observed.png alone needs the observed image: its rows are kept as 8-bit
// samples unless sheet.png, observed.tif or 16 bits show it.
bool observed_to_sink(const OutputOptions& outputs) {
  return !outputs.sheet && !outputs.float_outputs && outputs.image_depth == PngDepth::k8;
}

std::string image_subject(const ImageShape& shape, std::size_t extra) {
  return "a run on this " + std::to_string(shape.width) + " x " + std::to_string(shape.height) +
         " x " + std::to_string(shape.channels) + " image" +
         (extra > 0 ? " with its extra outputs (sheet, report, float or 16-bit)" : "");
}

// Refuses, from the PNG header alone, a run the memory guard would refuse
// after decoding (the same estimate: the header gives the channels and the
// bit depth), so that a huge image fails before it is decoded.
void check_memory_from_header(const std::optional<PngHeaderSize>& size, const std::string& input,
                              const SimulationOptions& options, const ShutterCode& code,
                              const FolderRunOptions& run) {
  if (options.max_memory_bytes == 0 || !size) return;
  OutputOptions outputs = run.outputs;
  outputs.image_depth = image_depth(run, size->bit_depth);
  const ImageShape shape{size->width, size->height, size->channels};
  const std::size_t extra = output_encoding_bytes_per_sample(outputs, size->channels);
  unless_simulate_refuses([&] {
    check_run_memory(shape, options, code, observed_to_sink(outputs), extra,
                     "input '" + input + "': " + image_subject(shape, extra));
  });
}

// The same after decoding, with the memory of the outputs beyond the
// default ones (Simulate checks the rest).
void check_outputs_memory(const Image& image, const SimulationOptions& options,
                          const ShutterCode& code, const OutputOptions& outputs) {
  const std::size_t extra = output_encoding_bytes_per_sample(outputs, image.channels);
  if (options.max_memory_bytes == 0 || extra == 0) return;
  const ImageShape shape{image.width, image.height, image.channels};
  unless_simulate_refuses([&] {
    check_run_memory(shape, options, code, observed_to_sink(outputs), extra,
                     image_subject(shape, extra));
  });
}

void announce(const FolderRunOptions& run, const std::string& stage) {
  if (run.on_stage) run.on_stage(stage);
}

std::string describe_simulation(const std::string& input, const Image& image) {
  return "simulating input '" + input + "' (" + std::to_string(image.width) + "x" +
         std::to_string(image.height) + ", " + std::to_string(image.channels) +
         (image.channels == 1 ? " channel)" : " channels)");
}

// Simulate, with the early plan when it fits the image.
SimulationReport simulate_with(EarlyPlan& plan, const SimulationOptions& options,
                               const Image& image, const ShutterCode& code, ObservedRowSink* sink) {
  const std::optional<SimulationPlan> made = plan.valid() ? plan.get() : std::nullopt;
  if (made && made->fits(options, image.width, code)) {
    return Simulate(*made, options, image, code, sink);
  }
  return Simulate(options, image, code, sink);
}

}  // namespace

// While the image is read, when options.threads allows more than one thread, code.png and
// spectrum.png are drawn and the simulation plan is made on their own threads; the observed image
// is kept as 8-bit samples when no output needs it as doubles.
SimulationReport SimulateToFolder(const std::string& input_path, const ShutterCode& code,
                                  const std::filesystem::path& outdir,
                                  const SimulationOptions& options, const FolderRunOptions& run) {
  PlotsAhead plots;
  plots.in_progress = start_plots(code, options, run.outputs.plots);
  announce(run, "reading input '" + input_path + "'");
  const std::optional<PngHeaderSize> header = plausible_png_header(input_path);
  check_memory_from_header(header, input_path, options, code, run);
  EarlyPlan plan = start_plan(header, options, code);
  ImageFileInfo input_info;
  const Image image = read_image(input_path, options.max_memory_bytes, &input_info);
  OutputOptions outputs = run.outputs;
  outputs.image_depth = image_depth(run, input_info.bits_per_sample);
  if (const auto& d = options.velocity_distribution;
      d && d->kind == VelocityDistributionKind::kDiscrete) {
    outputs.other_inputs.push_back(d->source);  // its file is an input too: never overwritten
  }
  announce(run, describe_simulation(input_path, image));
  std::optional<ObservedPng8> observed_png8;
  if (observed_to_sink(outputs)) observed_png8.emplace(image.height, image.channels);
  check_outputs_memory(image, options, code, outputs);
  SimulationReport report =
      simulate_with(plan, options, image, code, observed_png8 ? &*observed_png8 : nullptr);
  if (run.on_simulated) run.on_simulated(report);
  announce(run, "writing the outputs to '" + outdir.string() + "'");
  if (observed_png8) {
    write_outputs(outdir, report, *observed_png8, image, input_path, outputs, plots);
  } else {
    write_outputs(outdir, report, image, input_path, outputs, plots);
  }
  return report;
}

}  // namespace fss
