// What the files of a run are made from: the argument of RunFile::make
// (io/run_files.h), filled in by write_outputs.
#pragma once

#include <functional>
#include <future>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/pipeline/simulate.h"
#include "io/observed_png8.h"
#include "io/run_files.h"
#include "io/run_plots.h"

namespace fss {

// Where observed.png comes from: the observed image the report kept, or
// the rows an ObservedPng8 collected while the run kept none.
using ObservedSource =
    std::variant<std::reference_wrapper<const Image>, std::reference_wrapper<const ObservedPng8>>;

struct RunFileSources {
  const SimulationReport& report;
  const Image& input;             // the image the report was made from
  const std::string& input_path;  // as given, for report.json and report.html
  ObservedSource observed;
  const std::optional<RunPlots>& plots_drawn_ahead;
  const std::shared_future<RunPlots>& plots_in_progress;
  const std::vector<std::string>& names;  // every file written, in order
  PngDepth image_depth = PngDepth::k8;    // of observed, restored, groundtruth, residual.png

  // The plots drawn ahead: ready, or waited for while another thread draws
  // them; null when the outputs draw them.
  const RunPlots* drawn_plots() const {
    if (plots_drawn_ahead) return &*plots_drawn_ahead;
    return plots_in_progress.valid() ? &plots_in_progress.get() : nullptr;
  }
};

}  // namespace fss
