#include "fss/campaign/table.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "campaign/column_roles.h"
#include "campaign/table_model.h"
#include "campaign/table_numbers.h"
#include "campaign/user_input.h"
#include "fss/campaign/check.h"
#include "fss/campaign/results.h"
#include "fss/core/error.h"

namespace fss {

namespace {

using column_roles::Role;
using table_model::Cell;
using table_model::Column;
using table_model::Table;
using table_numbers::parse_number;

// A results file: its header and rows, cells found by column name.
struct Results {
  std::string name;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  bool has(const std::string& column) const {
    return std::find(header.begin(), header.end(), column) != header.end();
  }
  const std::string& cell(std::size_t row, const std::string& column) const {
    static const std::string empty;
    const auto it = std::find(header.begin(), header.end(), column);
    return it == header.end() ? empty : rows[row][it - header.begin()];
  }
};

std::string quoted(const std::string& text) { return "'" + escape_control_characters(text) + "'"; }

Results parse_results(const std::string& text, const std::string& name) {
  std::vector<std::vector<std::string>> rows = parse_csv(text, name);
  if (rows.empty()) throw_usage_error(quoted(name) + " is empty, not a campaign's results.csv");
  Results r{name, rows.front(), {rows.begin() + 1, rows.end()}};
  for (const char* needed : {"status", "trials"}) {
    if (!r.has(needed)) {
      throw_usage_error(quoted(name) + " is not a campaign's results.csv: it has no column '" +
                        needed + "'");
    }
  }
  if (r.rows.empty()) throw_usage_error(quoted(name) + " has no rows: nothing to tabulate");
  return r;
}

bool same_in_every_row(const Results& r, const std::string& column) {
  for (std::size_t i = 1; i < r.rows.size(); ++i) {
    if (r.cell(i, column) != r.cell(0, column)) return false;
  }
  return true;
}

// Whether restore_velocity only repeats the velocity (or is empty) in every
// row: then it is no setting of its own.
bool restore_velocity_follows(const Results& r) {
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const std::string& restore = r.cell(i, "restore_velocity");
    if (!restore.empty() && restore != r.cell(i, "velocity")) return false;
  }
  return true;
}

// The settings a table may show or put in its caption: the setting columns
// of the file, restore_velocity only when it is a setting of its own.
std::vector<std::string> setting_columns(const Results& r) {
  std::vector<std::string> settings;
  for (const std::string& column : r.header) {
    const column_roles::ColumnRole* role = column_roles::find(column);
    if (role == nullptr || role->role != Role::kSetting) continue;
    if (column == "restore_velocity" && restore_velocity_follows(r)) continue;
    settings.push_back(column);
  }
  return settings;
}

// The default columns: the settings that vary, the trials when they vary,
// then the measured means and their predictions.
std::vector<std::string> default_columns(const Results& r) {
  std::vector<std::string> columns;
  for (const std::string& setting : setting_columns(r)) {
    if (!same_in_every_row(r, setting)) columns.push_back(setting);
  }
  if (!same_in_every_row(r, "trials")) columns.push_back("trials");
  bool distributions = false;
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    distributions = distributions || !r.cell(i, "velocity_distribution").empty();
  }
  const std::vector<std::string> quantities =
      distributions ? std::vector<std::string>{"mse_mean", "predicted_mse", "rmse_ci_mean"}
                    : std::vector<std::string>{"rmse_mean", "predicted_rmse", "rmse_ci_mean"};
  for (const std::string& q : quantities) {
    if (r.has(q)) columns.push_back(q);
  }
  return columns;
}

// A usage error unless every column asked is a results column the file has,
// once, with the sd a statistic's standard error needs.
void check_columns(const Results& r, const std::vector<std::string>& columns) {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const std::string& column = columns[i];
    const column_roles::ColumnRole* role = column_roles::find(column);
    if (role == nullptr) {
      throw_usage_error("table column " + quoted(column) +
                        " is not a column of a campaign's results.csv (docs/campaign.md)");
    }
    if (std::find(columns.begin(), columns.begin() + i, column) != columns.begin() + i) {
      throw_usage_error("table column " + quoted(column) + " is asked twice");
    }
    if (!r.has(column)) throw_usage_error(quoted(r.name) + " has no column " + quoted(column));
    const std::string sd(role->partner);
    if (role->role == Role::kStatistic && !r.has(sd)) {
      std::string message = quoted(r.name);
      message.append(" has no column '").append(sd).append("', which the standard error of ");
      message.append(column).append(" needs");
      throw_usage_error(message);
    }
  }
}

ColumnKind kind_of(const std::string& column) {
  const int index = campaign_column_index(column);
  return index < 0 ? ColumnKind::kText : campaign_columns(true)[index].kind;
}

// The standard error of statistic `column` in `row`, sd / sqrt(trials), when
// the row has its sd and at least 2 trials.
std::optional<double> standard_error(const Results& r, std::size_t row, const std::string& column) {
  const column_roles::ColumnRole* role = column_roles::find(column);
  const std::optional<double> sd = parse_number(r.cell(row, std::string(role->partner)));
  const std::optional<double> trials = parse_number(r.cell(row, "trials"));
  if (!sd || !trials || !std::isfinite(*sd) || *sd < 0.0 || !(*trials >= 2.0)) return std::nullopt;
  return *sd / std::sqrt(*trials);
}

// The measured mean a prediction is read against: the prediction is rounded
// to the place of that mean's standard error.
const char* measured_partner(const std::string& column) {
  if (column == "predicted_rmse" || column == "predicted_rmse_noise_free") return "rmse_mean";
  if (column == "predicted_mse") return "mse_mean";
  return nullptr;
}

Cell number(const table_numbers::Rounded& value) { return {Cell::Kind::kNumber, "", value, {}}; }

// A mean ± its standard error (digits significant digits, the mean to the
// same place); the mean alone, to digits + 2 significant digits, without a
// standard error (one trial, no sd) or when infinite.
Cell statistic_cell(const Results& r, std::size_t row, const std::string& column, int digits) {
  const std::optional<double> mean = parse_number(r.cell(row, column));
  if (!mean) return {};
  const std::optional<double> se = standard_error(r, row, column);
  if (!se || !std::isfinite(*mean))
    return number(table_numbers::round_significant(*mean, digits + 2));
  Cell cell{Cell::Kind::kMeanSe, "", {}, {}};
  if (*se > 0.0) {
    const table_numbers::MeanSe rounded = table_numbers::round_mean_se(*mean, *se, digits);
    cell.value = rounded.mean;
    cell.se = rounded.se;
  } else {
    cell.value = table_numbers::round_significant(*mean, digits + 2);
    cell.se = {"0", cell.value.exponent};
  }
  return cell;
}

// Any other number: a prediction to the place of its measured mean's
// standard error, an sd to `digits` significant digits, the rest to digits + 2.
Cell number_cell(const Results& r, std::size_t row, const std::string& column, int digits) {
  const std::optional<double> value = parse_number(r.cell(row, column));
  if (!value) return {};
  if (const char* partner = measured_partner(column); partner != nullptr && r.has(partner)) {
    if (const std::optional<double> se = standard_error(r, row, partner); se && *se > 0.0) {
      return number(table_numbers::round_to_place(*value, table_numbers::last_place(*se, digits)));
    }
  }
  const bool spread = column_roles::find(column)->role == Role::kSpread;
  return number(table_numbers::round_significant(*value, spread ? digits : digits + 2));
}

Cell make_cell(const Results& r, std::size_t row, const std::string& column, int digits) {
  const Role role = column_roles::find(column)->role;
  if (role == Role::kStatistic) return statistic_cell(r, row, column, digits);
  const bool as_text = role == Role::kSetting || role == Role::kTrials || role == Role::kProvenance;
  if (kind_of(column) == ColumnKind::kNumber && !as_text) {
    return number_cell(r, row, column, digits);
  }
  const std::string& text = r.cell(row, column);
  return text.empty() ? Cell{} : Cell{Cell::Kind::kText, text, {}, {}};
}

// The table of the columns `names` (checked), status added when a row did
// not run ok, the constant settings not shown and the trials for the caption.
Table build_table(const Results& r, std::vector<std::string> names, int digits) {
  check_columns(r, names);
  bool all_ok = true;
  for (std::size_t i = 0; i < r.rows.size(); ++i) all_ok = all_ok && r.cell(i, "status") == "ok";
  const auto shown = [&names](const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  if (!all_ok && !shown("status")) names.push_back("status");
  Table table;
  for (const std::string& name : names) {
    table.columns.push_back({name, column_roles::find(name)->role == Role::kStatistic,
                             kind_of(name) == ColumnKind::kNumber});
  }
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    std::vector<Cell> cells;
    cells.reserve(names.size());
    for (const std::string& name : names) cells.push_back(make_cell(r, i, name, digits));
    table.rows.push_back(std::move(cells));
  }
  for (const std::string& setting : setting_columns(r)) {
    if (!shown(setting) && same_in_every_row(r, setting) && !r.cell(0, setting).empty()) {
      table.fixed.emplace_back(setting, r.cell(0, setting));
    }
  }
  if (!shown("trials") && same_in_every_row(r, "trials")) table.trials = r.cell(0, "trials");
  return table;
}

}  // namespace

std::optional<TableFormat> table_format_from_string(std::string_view text) {
  if (text == "markdown") return TableFormat::kMarkdown;
  if (text == "latex") return TableFormat::kLatex;
  if (text == "csv") return TableFormat::kCsv;
  return std::nullopt;
}

bool TableOptions::IsValid(std::string* error) const {
  if (digits < kMinTableDigits || digits > kMaxTableDigits) {
    *error = "digits " + std::to_string(digits) + ": expected an integer in [" +
             std::to_string(kMinTableDigits) + ", " + std::to_string(kMaxTableDigits) + "]";
    return false;
  }
  return true;
}

std::string campaign_table(const std::string& results_csv, const std::string& results_name,
                           const TableOptions& options) {
  if (std::string error; !options.IsValid(&error)) throw_usage_error("table " + error);
  const Results results = parse_results(results_csv, results_name);
  const std::vector<std::string> names =
      options.columns.empty() ? default_columns(results) : options.columns;
  return table_model::render(build_table(results, names, options.digits), options.format);
}

std::string campaign_table_file(const std::string& results_path, const TableOptions& options) {
  return campaign_table(
      campaign_input::read_text_file(results_path, kMaxCheckFileBytes, "results file"),
      results_path, options);
}

}  // namespace fss
