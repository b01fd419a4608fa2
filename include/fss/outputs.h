// Writing a run's outputs: all files are staged and renamed into place only
// once every one of them has been written, so a failed run leaves nothing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fss/simulate.h"

namespace fss {

// |K(xi)| for xi = -pi + j 2 pi / 100, j = 0 .. 99, "xi |K|" per line (the
// reference program's spectrum.txt).
std::string format_spectrum_txt(const std::vector<double>& gains, double velocity, double dt);

// report.json content; `input_path` is recorded as given.
nlohmann::json report_json(const SimulationReport& report, const std::string& input_path);

// Names of the files write_outputs creates.
std::vector<std::string> output_file_names();

// Writes observed.png, restored.png, groundtruth.png, residual.png, code.txt,
// spectrum.txt and report.json into `outdir` (created if missing); `input` is
// the image the report was made from (for the ground truth and the residual,
// encoded from it row by row). Refuses, before writing anything, to replace
// `input_path` or to write into a path that is not a directory. Throws a
// runtime fss::Error on failure, after removing whatever it staged.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path);

}  // namespace fss
