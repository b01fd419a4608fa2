// The rows of a campaign (results.csv, trials.csv: text cells in the schema's columns) as a dict
// of numpy columns, for fss.run_campaign and fss.read_campaign.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace fss::python {

namespace py = pybind11;

// A dict column name -> numpy array of one entry per row, in the columns' order: float64 for the
// numbers of the results schema (NaN where a cell is empty; "inf", "nan" as floats) and for its
// booleans (1.0 true, 0.0 false, NaN empty); int64 for the counts trials, adc_bits and trial;
// uint64 for the seeds seed and trial_seed; str for the text columns and any column the schema
// does not name. A cell that does not read as its column's type is a RuntimeError naming
// `source`, the column and the row.
py::dict campaign_columns_dict(const std::vector<std::string>& names,
                               const std::vector<std::vector<std::string>>& rows,
                               const std::string& source);

}  // namespace fss::python
