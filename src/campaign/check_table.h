// What the two checks of `campaign check` share (src/campaign/check.cpp against EXPECTED.csv,
// check_predictions.cpp against the rows' own predictions): a CSV table with its columns by
// name, the cells as numbers, the names in messages, and the default k of the k-SE rule.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace fss::check_table {

// A file name in a message: quoted, control bytes escaped.
std::string shown(const std::string& name);

// A cell or column name in a message: one short line.
std::string cell_text(const std::string& text);

// The cell as a number; NaN when empty or not wholly a number.
double number(const std::string& text);

// A CSV table (parse_csv) with its columns by name.
struct Table {
  std::vector<std::vector<std::string>> rows;  // rows[0] is the header
  std::map<std::string, int> column;

  Table(const std::string& text, const std::string& name);
  bool has(const std::string& name) const { return column.count(name) != 0; }
  // The cell of column `name` in `row`; nullptr when the table has no such column.
  const std::string* cell(std::size_t row, const std::string& name) const;
};

// The default k of the k-SE rule over `comparisons` comparisons: the two-sided quantile of
// Student's t with the comparison's degrees of freedom at kCheckFalseAlarmRate / comparisons
// (Bonferroni), cached by degrees of freedom.
class DefaultK {
 public:
  explicit DefaultK(long long comparisons);
  double at(double degrees_of_freedom);
  // "k = 5.53 standard errors (Student-t, 19 degrees of freedom: ...)", or "k = 5.5 to 6.1
  // ... 9 to 19 ..." over the degrees of freedom used so far, and the false-alarm rate.
  std::string text() const;

 private:
  long long comparisons_;
  std::map<double, double> k_;  // degrees of freedom -> k
};

// "within K_TEXT, or abs A, or rel R" (each part when not empty or 0); "equal" for none.
std::string tolerance_text(double abs, double rel, const std::string& k_text);

}  // namespace fss::check_table
