// report.json of a run: every parameter and result (docs/report-schema.md).
#pragma once

#include <string>

#include "fss/pipeline/simulate.h"

namespace fss {

// The version of report.json's layout, recorded in it as "schema_version"
// (docs/report-schema.md lists every field): raised whenever a field is
// renamed, removed or changes meaning; added fields do not raise it.
inline constexpr int kReportSchemaVersion = 1;

// The version recorded in report.json as "fssim_version": what
// `fssim --version` prints after "fssim ", with the git revision of a build
// from a checkout ("0.1.0 (git 0396604)").
std::string report_fssim_version();

// The bytes of report.json, indented by 2, and a line end. Paths
// are bytes: one that is not UTF-8 is kept with U+FFFD in place of its
// invalid bytes rather than failing the run.
std::string report_json_text(const SimulationReport& report, const std::string& input_path);

}  // namespace fss
