// Private to the campaign tables: a table of results as table.cpp builds it
// (columns, rounded cells, the caption's fixed settings) and its rendering in
// each format (table_render.cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "campaign/table_numbers.h"
#include "fss/campaign/table.h"

namespace fss::table_model {

struct Cell {
  enum class Kind { kEmpty, kText, kNumber, kMeanSe };
  Kind kind = Kind::kEmpty;
  std::string text;              // kText: as in results.csv
  table_numbers::Rounded value;  // kNumber, and the mean of kMeanSe
  table_numbers::Rounded se;     // kMeanSe
};

struct Column {
  std::string name;        // the results column ("rmse_mean")
  bool statistic = false;  // cells are mean ± SE
  bool number = false;     // a numeric column: right-aligned
};

struct Table {
  std::vector<Column> columns;
  std::vector<std::vector<Cell>> rows;
  // The settings that are the same in every row and not shown, (name, value).
  std::vector<std::pair<std::string, std::string>> fixed;
  std::string trials;  // the trials of every row, when the same and not shown; else empty
};

// The table as text in `format`: Markdown (a caption line, then a pipe table),
// LaTeX (the caption as comment lines, then a booktabs tabular) or CSV (a
// header line, the statistics as NAME and NAME_se columns, no caption).
std::string render(const Table& table, TableFormat format);

}  // namespace fss::table_model
