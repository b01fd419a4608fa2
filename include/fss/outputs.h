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
// spectrum.txt and report.json into `outdir` (created if missing). Refuses,
// before writing anything, to replace `input_path` or any of `other_inputs`
// (such as the code file) or to write into a path that is not a directory.
// Each file is first written under a new hidden name in `outdir` and renamed
// into place only once all are complete. Throws a runtime fss::Error on
// failure (a usage one for an empty `outdir`), after removing whatever it
// staged: existing files are never touched then.
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const std::string& input_path, const std::vector<std::string>& other_inputs);
void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const std::string& input_path);

}  // namespace fss
