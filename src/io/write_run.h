// write_outputs with what the fast path of a run gives it (SimulateToFolder):
// the observed rows as 8-bit samples, and the plots drawn ahead.
#pragma once

#include <filesystem>
#include <future>
#include <optional>
#include <string>

#include "fss/core/image.h"
#include "fss/io/outputs.h"
#include "fss/pipeline/simulate.h"
#include "io/observed_png8.h"
#include "io/run_files.h"
#include "io/run_plots.h"

namespace fss {

// code.png and spectrum.png drawn ahead for the report's code and motion
// (render_run_plots): ready, or being drawn on another thread, when the
// files that show them wait for them and the others are made meanwhile.
// Neither: write_outputs draws them. Plots drawn for another run are a
// usage error.
struct PlotsAhead {
  std::optional<RunPlots> drawn;
  std::shared_future<RunPlots> in_progress;
};

// Whether a file written `when` is written under `options`.
bool is_written(RunFileCondition when, const OutputOptions& options);

// write_outputs (outputs.h) with the plots drawn ahead.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path, const OutputOptions& options,
                   const PlotsAhead& plots);

// The same with observed.png made from the rows `observed` collected during
// the run (which then need not keep its observed image): it must hold every
// row, at the size of the report's outputs. sheet.png, the float outputs and
// 16-bit PNGs need the kept image.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const ObservedPng8& observed, const Image& input, const std::string& input_path,
                   const OutputOptions& options = {}, const PlotsAhead& plots = {});

}  // namespace fss
