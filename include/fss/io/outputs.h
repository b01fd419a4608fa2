// Writing a run's outputs: all files are staged and renamed into place only
// once every one of them has been written, so a failed run leaves nothing.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fss/pipeline/simulate.h"

namespace fss {

// |K(xi)| for xi = -pi + j 2 pi / 100, j = 0 .. 99, "xi |K|" per line (the
// reference program's spectrum.txt).
std::string format_spectrum_txt(const std::vector<double>& gains, double velocity, double dt);

// report.json content; `input_path` is recorded as given.
nlohmann::json report_json(const SimulationReport& report, const std::string& input_path);

// The observed image as the 8-bit samples observed.png holds, collected row
// by row as the ObservedRowSink of Simulate, so that the report need not
// keep the observed image: one byte a sample instead of a double. Rows may
// arrive concurrently; the width is that of the first.
class ObservedPng8 : public ObservedRowSink {
 public:
  ObservedPng8(int height, int channels);
  ObservedPng8(const ObservedPng8&) = delete;
  ObservedPng8& operator=(const ObservedPng8&) = delete;

  // Stores one row; consume_row calls this. A row that does not fit or is
  // stored twice is a usage error.
  void store_row(int channel, int row, std::span<const double> values);
  void consume_row(int channel, int row, std::span<const double> values) override {
    store_row(channel, row, values);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  // Rows stored so far (channels x height when complete).
  int rows_stored() const { return rows_stored_; }
  // The PNG; the same bytes as encode_png8 of the observed image of doubles.
  std::vector<std::uint8_t> encode() const;

 private:
  int width_ = 0;
  int height_;
  int channels_;
  std::once_flag allocated_;
  std::vector<std::uint8_t> samples_;      // planar, like Image
  std::vector<std::atomic<bool>> stored_;  // by channel * height + row
  std::atomic<int> rows_stored_{0};
};

// code.png and spectrum.png of a run. They depend only on the code and the
// motion, so a caller can draw them on another thread while Simulate runs
// and hand them to write_outputs (OutputOptions::rendered_plots). Drawing
// is serialized inside PLplot: it overlaps the simulation, not other plots.
struct RunPlots {
  std::string code_name;  // what they were drawn for, checked by write_outputs
  std::vector<double> gains;
  double velocity_px_per_slot = 0.0;
  double restore_velocity_px_per_slot = 0.0;
  double dt = 0.0;
  std::vector<std::uint8_t> code_png;
  std::vector<std::uint8_t> spectrum_png;
};

// Draws the plots write_outputs would draw for a run of `code` with
// `options`: the same bytes.
RunPlots render_run_plots(const ShutterCode& code, const SimulationOptions& options);

// Optional outputs of a run.
struct OutputOptions {
  bool plots = true;         // code.png and spectrum.png (plot.h)
  bool sheet = false;        // sheet.png: observed | restored | residual
  bool html_report = false;  // report.html (html_report.h)
  // Files besides the input image that must never be overwritten (the code file).
  std::vector<std::string> other_inputs;
  // Where observed.png comes from when the report does not keep the observed
  // image (Simulate sent its rows to this sink); it must then hold
  // every row, at the size of the report's outputs. sheet.png needs the
  // kept image.
  const ObservedPng8* observed_png8 = nullptr;
  // Plots drawn ahead (render_run_plots) for the report's code and motion,
  // used instead of drawing them again; a usage error if they do not match.
  const RunPlots* rendered_plots = nullptr;
};

// Names of the files write_outputs creates.
std::vector<std::string> output_file_names(const OutputOptions& options = {});

// sheet.png: the observed, restored and residual images side by side under a
// title naming the code, the parameters and the measured errors; `input` is
// the image the report was made from.
std::vector<std::uint8_t> figure_sheet_png(const SimulationReport& report, const Image& input);

// Writes observed.png, restored.png, groundtruth.png, residual.png, code.txt,
// spectrum.txt and report.json into `outdir` (created if missing), and the
// files `options` asks for; `input` is the image the report was made from
// (the ground truth and the residual are encoded from it row by row).
// Refuses, before writing anything, to replace `input_path` or any of
// `options.other_inputs` (such as the code file) or to write into a path that
// is not a directory. Each file is first written under a new hidden name in
// `outdir` and renamed into place only once all are complete. Throws a
// runtime fss::Error on failure (a usage one for an empty `outdir`), after
// removing whatever it staged: existing files are never touched then.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options = {});

// Writes `bytes` to `path` through a temporary file in the same directory
// renamed into place, so `path` is either untouched or complete. Throws a
// runtime fss::Error naming the file on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace fss
