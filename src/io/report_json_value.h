// report.json as a JSON value, for the Python module and the tests; the
// public header (fss/io/report_json.h) gives its text.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fss/io/report_json.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// report.json content; `input_path` is recorded as given. Infinite and NaN
// values are null.
nlohmann::json report_json(const SimulationReport& report, const std::string& input_path);

}  // namespace fss
