#include "campaign_columns.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>
#include <system_error>

#include "fss/campaign/results.h"
#include "fss/core/error.h"

namespace fss::python {

namespace {

enum class ColumnType { kFloat, kBoolean, kInt64, kUint64, kText };

// The type of a column by its name in the results and trials schemas (the widest, version 4).
ColumnType column_type(std::string_view name) {
  if (name == "trials" || name == "adc_bits" || name == "trial") return ColumnType::kInt64;
  if (name == "seed" || name == "trial_seed") return ColumnType::kUint64;
  for (const auto* columns : {&fss::campaign_columns(true), &fss::trial_columns(true)}) {
    for (const fss::ResultColumn& column : *columns) {
      if (name != column.name) continue;
      if (column.kind == fss::ColumnKind::kNumber) return ColumnType::kFloat;
      if (column.kind == fss::ColumnKind::kBoolean) return ColumnType::kBoolean;
      return ColumnType::kText;
    }
  }
  return ColumnType::kText;
}

[[noreturn]] void refuse_cell(const std::string& source, const std::string& name, std::size_t row,
                              const std::string& cell, const char* expected) {
  fss::throw_runtime_error(source + ": column " + name + ", row " + std::to_string(row + 1) +
                           ": '" + fss::shorten_for_message(cell) + "' is not " + expected);
}

// The whole cell as a T (std::from_chars: a double correctly rounded, "inf" and "nan" too).
template <typename T>
bool parse_whole(const std::string& cell, T* value) {
  const char* end = cell.data() + cell.size();
  const auto [at, error] = std::from_chars(cell.data(), end, *value);
  return error == std::errc() && at == end;
}

// The cells of column `j` as a T array: `parse` gives the value of each (false: not one).
template <typename T, typename Parse>
py::array typed_column(const std::vector<std::vector<std::string>>& rows, std::size_t j,
                       Parse parse) {
  py::array_t<T> array(static_cast<py::ssize_t>(rows.size()));
  T* out = array.mutable_data();
  for (std::size_t i = 0; i < rows.size(); ++i) out[i] = parse(rows[i][j], i);
  return array;
}

py::array column_array(const std::string& name, const std::vector<std::vector<std::string>>& rows,
                       std::size_t j, const std::string& source) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  switch (column_type(name)) {
    case ColumnType::kFloat:
      return typed_column<double>(rows, j, [&](const std::string& cell, std::size_t i) {
        double value = nan;
        if (!cell.empty() && !parse_whole(cell, &value))
          refuse_cell(source, name, i, cell, "a number");
        return value;
      });
    case ColumnType::kBoolean:
      return typed_column<double>(rows, j, [&](const std::string& cell, std::size_t i) {
        if (cell.empty()) return nan;
        if (cell != "true" && cell != "false") refuse_cell(source, name, i, cell, "true or false");
        return cell == "true" ? 1.0 : 0.0;
      });
    case ColumnType::kInt64:
      return typed_column<std::int64_t>(rows, j, [&](const std::string& cell, std::size_t i) {
        std::int64_t value = 0;
        if (!parse_whole(cell, &value)) refuse_cell(source, name, i, cell, "an integer");
        return value;
      });
    case ColumnType::kUint64:
      return typed_column<std::uint64_t>(rows, j, [&](const std::string& cell, std::size_t i) {
        std::uint64_t value = 0;
        if (!parse_whole(cell, &value)) refuse_cell(source, name, i, cell, "a 64-bit seed");
        return value;
      });
    case ColumnType::kText:
      break;
  }
  py::list cells;
  for (const std::vector<std::string>& row : rows) {
    PyObject* text = PyUnicode_DecodeUTF8(row[j].data(), static_cast<Py_ssize_t>(row[j].size()),
                                          "backslashreplace");
    if (text == nullptr) throw py::error_already_set();
    cells.append(py::reinterpret_steal<py::str>(text));
  }
  return py::module_::import("numpy").attr("array")(cells, py::arg("dtype") = "str");
}

// Every name a column of results.csv or trials.csv (the widest schemas), each once.
void check_header(const std::vector<std::string>& names, const std::string& source) {
  const auto known = [](const std::string& name) {
    for (const auto* columns : {&fss::campaign_columns(true), &fss::trial_columns(true)}) {
      for (const fss::ResultColumn& column : *columns) {
        if (name == column.name) return true;
      }
    }
    return false;
  };
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (!known(names[j])) {
      fss::throw_runtime_error(source + ": column '" + fss::shorten_for_message(names[j], 40) +
                               "' is not one of results.csv or trials.csv (expected the "
                               "results of fssim campaign)");
    }
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(j), names[j]) !=
        names.begin() + static_cast<std::ptrdiff_t>(j)) {
      fss::throw_runtime_error(source + ": column '" + names[j] + "' appears twice");
    }
  }
}

}  // namespace

py::dict campaign_columns_dict(const std::vector<std::string>& names,
                               const std::vector<std::vector<std::string>>& rows,
                               const std::string& source) {
  check_header(names, source);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != names.size()) {
      fss::throw_runtime_error(source + ": row " + std::to_string(i + 1) + " has " +
                               std::to_string(rows[i].size()) + " cells, the header " +
                               std::to_string(names.size()));
    }
  }
  py::dict columns;
  for (std::size_t j = 0; j < names.size(); ++j) {
    columns[py::str(names[j])] = column_array(names[j], rows, j, source);
  }
  return columns;
}

}  // namespace fss::python
