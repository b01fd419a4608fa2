// campaign check --predicted: each row's measured mean against its own prediction.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "campaign/check_table.h"
#include "campaign/column_roles.h"
#include "campaign/user_input.h"
#include "fss/campaign/check.h"
#include "fss/core/error.h"

namespace fss {

using check_table::cell_text;
using check_table::number;
using check_table::shown;
using check_table::Table;

namespace {

// "line 3: code=raskar snr=200": the row's line and its setting columns whose values differ
// between rows of `t` (those that tell the rows apart).
std::string row_label(const Table& t, std::size_t row) {
  std::string label = "line " + std::to_string(row + 1) + ":";
  for (const column_roles::ColumnRole& role : column_roles::all()) {
    const auto it = t.column.find(std::string(role.name));
    if (role.role != column_roles::Role::kSetting || it == t.column.end()) continue;
    const bool varies = std::any_of(t.rows.begin() + 1, t.rows.end(), [&](const auto& r) {
      return r[it->second] != t.rows[1][it->second];
    });
    if (varies) label += " " + it->first + "=" + cell_text(t.rows[row][it->second]);
  }
  return label;
}

// `text` in single quotes.
std::string in_quotes(const std::string& text) {
  std::string quoted = "'";
  quoted += text;
  quoted += '\'';
  return quoted;
}

// A row's measured mean and its prediction.
struct Measured {
  std::size_t row = 0;
  const char* measured = "";
  const char* predicted = "";
  double se = 0.0;  // sd / sqrt(trials)
  double nu = 0.0;  // trials - 1
};

// Row `r`'s mean `measured` against its prediction `predicted`, the standard error from `sd` and
// the trials; nullopt when the row has none to compare (not ok, < 2 trials, no finite prediction).
std::optional<Measured> measured_of(const Table& t, std::size_t r, const char* measured,
                                    const char* predicted, const char* sd) {
  const double n = number(*t.cell(r, "trials")), p = number(*t.cell(r, predicted));
  if (*t.cell(r, "status") != "ok" || !(n >= kMinStandardErrorTrials) || !std::isfinite(p)) {
    return std::nullopt;
  }
  return Measured{r, measured, predicted, number(*t.cell(r, sd)) / std::sqrt(n), n - 1.0};
}

// The comparison of `m` within abs, rel times |prediction| or k standard errors.
CheckCase prediction_case(const Table& t, const Measured& m, double abs, double rel, double k) {
  const std::size_t r = m.row;
  const std::string& got = *t.cell(r, m.measured);
  const std::string& predicted = *t.cell(r, m.predicted);
  const double value = number(got), p = number(predicted);
  if (std::isnan(value)) {  // no measured mean to compare: a deviation, without a difference
    std::string message = row_label(t, r) + " " + m.measured + " ";
    message += got.empty() ? std::string("missing") : in_quotes(cell_text(got));
    message += ", " + std::string(m.predicted) + " " + cell_text(predicted);
    return CheckCase{row_label(t, r), m.measured, false, message};
  }
  const double d = value - p;
  const double kse = k * m.se;
  const double tolerance = std::max({abs, rel * std::abs(p), std::isnan(kse) ? 0 : kse});
  CheckCase c{row_label(t, r), m.measured, std::abs(d) <= tolerance, ""};
  const std::string z = m.se > 0.0 ? ", z = " + format_number(d / m.se) : std::string();
  std::string rule = "abs " + format_exact(abs) + ", rel " + format_exact(rel);
  if (k > 0.0) {
    rule += std::isnan(kse) ? ", no standard error"
                            : ", " + format_number(k, 4) + " SE = " + format_number(kse);
  }
  c.message = c.setting + " " + m.measured + " " + cell_text(got) + ", " + m.predicted + " " +
              cell_text(predicted) + " (difference " + format_number(d) + z + "; tolerance " +
              format_number(tolerance) + ": " + rule + ")";
  return c;
}

// RESULTS' columns the check reads; *distributions tells whether it has schema 4's.
void check_prediction_columns(const Table& t, const std::string& results_name,
                              bool* distributions) {
  for (const char* c : {"status", "trials", "rmse_mean", "rmse_sd", "predicted_rmse"}) {
    if (!t.has(c)) {
      throw_usage_error(shown(results_name) + " has no column '" + c +
                        "': not the results.csv of a campaign");
    }
  }
  *distributions = t.has("velocity_distribution");
  for (const char* c : {"mse_mean", "mse_sd", "predicted_mse"}) {
    if (*distributions && !t.has(c)) {
      throw_usage_error(shown(results_name) + " has velocity_distribution but no column '" + c +
                        "': not the results.csv of a campaign");
    }
  }
}

}  // namespace

CheckReport CheckCampaignPredictions(const std::string& results_csv,
                                     const std::string& results_name, const CheckOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  if (!options.columns.empty()) {
    throw_usage_error(
        "--columns chooses the columns of EXPECTED.csv; the check against the "
        "predictions compares mse_mean or rmse_mean");
  }
  if (options.exact) {
    throw_usage_error(
        "--exact compares the exact columns of EXPECTED.csv; the check against the predictions "
        "compares means over trials");
  }
  const Table t(results_csv, results_name);
  bool distributions = false;
  check_prediction_columns(t, results_name, &distributions);
  std::vector<Measured> rows;
  for (std::size_t r = 1; r < t.rows.size(); ++r) {
    // Under a distribution, sqrt(E[MSE]) is above the mean RMSE (Jensen): MSE is compared.
    const bool mse = distributions && !t.cell(r, "velocity_distribution")->empty();
    const std::optional<Measured> m =
        mse ? measured_of(t, r, "mse_mean", "predicted_mse", "mse_sd")
            : measured_of(t, r, "rmse_mean", "predicted_rmse", "rmse_sd");
    if (m) rows.push_back(*m);
  }
  if (rows.empty()) {
    throw_usage_error(shown(results_name) +
                      " has no row to compare with its prediction (status ok, 2 trials or more, "
                      "a finite prediction): the check would check nothing");
  }
  const double abs = options.abs_tolerance.value_or(0.0);
  const double rel = options.rel_tolerance.value_or(kExactRelativeTolerance);
  // The default k when no tolerance is given (docs/campaign.md): over the rows compared.
  const bool default_k =
      !options.abs_tolerance && !options.rel_tolerance && !options.k_standard_errors;
  check_table::DefaultK k(static_cast<long long>(rows.size()));
  CheckReport report;
  std::string columns;
  for (const Measured& m : rows) {
    const double row_k = default_k ? k.at(m.nu) : options.k_standard_errors.value_or(0.0);
    report.cases.push_back(prediction_case(t, m, abs, rel, row_k));
    const std::string pair = std::string(m.measured) + " with " + m.predicted;
    if (columns.find(pair) == std::string::npos) columns += (columns.empty() ? "" : ", ") + pair;
  }
  const std::string k_text = default_k ? k.text()
                             : options.k_standard_errors && *options.k_standard_errors > 0.0
                                 ? format_exact(*options.k_standard_errors) + " standard errors"
                                 : "";
  report.summary = {"compared " + columns + ": " + check_table::tolerance_text(abs, rel, k_text)};
  return report;
}

CheckReport CheckCampaignPredictionFile(const std::string& results_path,
                                        const CheckOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const std::string results =
      campaign_input::read_text_file(results_path, kMaxCheckFileBytes, "results file");
  return CheckCampaignPredictions(results, results_path, options);
}

}  // namespace fss
