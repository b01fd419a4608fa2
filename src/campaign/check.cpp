#include "fss/campaign/check.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "campaign/campaign_text.h"
#include "campaign/user_input.h"
#include "core/text_util.h"
#include "fss/campaign/results.h"
#include "fss/core/error.h"

namespace fss {

int CheckReport::failures() const {
  int n = 0;
  for (const CheckCase& c : cases) n += c.passed ? 0 : 1;
  return n;
}

bool CheckOptions::IsValid(std::string* error) const {
  // Named as the options of 'campaign check' that set them.
  for (const auto& [name, value] :
       {std::pair{"--abs", abs_tolerance}, std::pair{"--rel", rel_tolerance},
        std::pair{"--k-se", k_standard_errors}}) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      if (error)
        *error = std::string(name) + " = " + format_exact(value) + ": must be finite and >= 0";
      return false;
    }
  }
  return true;
}

namespace {

// A file name in a message: quoted, control bytes escaped.
std::string shown(const std::string& name) {
  std::string text = "'";
  text += escape_control_characters(name);
  return text + "'";
}

// A cell or column name of a CSV file in a message: one short line.
std::string cell_text(const std::string& text) { return shorten_for_message(text, 80); }

}  // namespace

std::vector<std::vector<std::string>> parse_csv(const std::string& text, const std::string& name) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(std::move(field));
      field.clear();
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      row.push_back(std::move(field));
      field.clear();
      rows.push_back(std::move(row));
      row.clear();
    } else {
      field += c;
      any = true;
    }
  }
  if (quoted) throw_usage_error(shown(name) + ": a quoted field is not closed");
  if (!field.empty() || !row.empty()) {
    row.push_back(std::move(field));
    rows.push_back(std::move(row));
  }
  (void)any;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    if (rows[r].size() != rows[0].size()) {
      throw_usage_error(shown(name) + ": line " + std::to_string(r + 1) + " has " +
                        std::to_string(rows[r].size()) + " fields, the header " +
                        std::to_string(rows[0].size()));
    }
  }
  if (rows.empty()) throw_usage_error(shown(name) + ": no header line");
  return rows;
}

namespace {

const char* const kSettingColumns[] = {"image",
                                       "code",
                                       "mode",
                                       "velocity",
                                       "restore_velocity",
                                       "snr",
                                       "dt",
                                       "noise",
                                       "rmse_margin",
                                       "read_noise",
                                       "dark_current",
                                       "full_well",
                                       "adc_bits",
                                       "adc_gain",
                                       "restoration",
                                       "regularization",
                                       "prior",
                                       "velocity_distribution"};
const char* const kNotCompared[] = {"image_sha256", "code_sha256", "seed",         "trials",
                                    "rmse_sd",      "rmse_ci_sd",  "ssim_sd",      "mse_sd",
                                    "blur_length",  "message",     "fssim_version"};

bool is_setting(const std::string& c) {
  for (const char* s : kSettingColumns) {
    if (c == s) return true;
  }
  return false;
}

bool compared_by_default(const std::string& c) {
  for (const char* s : kNotCompared) {
    if (c == s) return false;
  }
  return !is_setting(c) && campaign_column_index(c) >= 0;
}

double number(const std::string& text) {
  if (text.empty()) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() ? v : std::nan("");
}

std::string base_name(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool same_setting_value(const std::string& column, const std::string& result,
                        const std::string& expected) {
  if (column == "image" && expected.find('/') == std::string::npos) {
    return base_name(result) == expected;
  }
  const double r = number(result), e = number(expected);
  if (!std::isnan(r) && !std::isnan(e))
    return std::abs(r - e) <= 1e-12 * std::max(1.0, std::abs(e));
  return result == expected;
}

// A CSV table with its columns by name.
struct Table {
  std::vector<std::vector<std::string>> rows;  // rows[0] is the header
  std::map<std::string, int> column;

  Table(const std::string& text, const std::string& name) : rows(parse_csv(text, name)) {
    for (std::size_t i = 0; i < rows[0].size(); ++i) column[rows[0][i]] = static_cast<int>(i);
  }
  const std::string* cell(std::size_t row, const std::string& name) const {
    const auto it = column.find(name);
    return it == column.end() ? nullptr : &rows[row][it->second];
  }
};

// k-SE tolerance of a *_mean quantity, NaN when a side lacks its sd or trials.
double standard_error(const Table& t, std::size_t row, const std::string& quantity) {
  const std::string stem = quantity.substr(0, quantity.size() - 5);
  const std::string* sd = t.cell(row, stem + "_sd");
  const std::string* n = t.cell(row, "trials");
  if (!sd || !n) return std::nan("");
  return number(*sd) / std::sqrt(number(*n));
}

struct Comparison {
  const Table& results;
  const Table& expected;
  const CheckOptions& options;

  CheckCase compare(std::size_t r, std::size_t e, const std::string& column,
                    const std::string& setting) const;
};

CheckCase Comparison::compare(std::size_t r, std::size_t e, const std::string& column,
                              const std::string& setting) const {
  CheckCase c{setting, column, false, ""};
  const std::string& got = *results.cell(r, column);
  const std::string& want = *expected.cell(e, column);
  const double g = number(got), w = number(want);
  if (std::isnan(w) || std::isinf(w)) {  // text, or a non-finite number: equal text
    c.passed = got == want;
    c.message = setting + ": " + cell_text(column) + " is '" + cell_text(got) + "', expected '" +
                cell_text(want) + "'";
    return c;
  }
  const double d = g - w;
  double tolerance = std::max(options.abs_tolerance, options.rel_tolerance * std::abs(w));
  std::string rule =
      "abs " + format_exact(options.abs_tolerance) + ", rel " + format_exact(options.rel_tolerance);
  if (options.k_standard_errors > 0.0 && column.size() > 5 &&
      column.compare(column.size() - 5, 5, "_mean") == 0) {
    const double se_r = standard_error(results, r, column),
                 se_e = standard_error(expected, e, column);
    if (!std::isnan(se_r) && !std::isnan(se_e)) {
      const double k = options.k_standard_errors * std::hypot(se_r, se_e);
      tolerance = std::max(tolerance, k);
      rule += ", " + format_exact(options.k_standard_errors) + " SE = " + format_number(k);
    }
  }
  c.passed = std::abs(d) <= tolerance;  // false for a missing or non-finite result
  // The difference only when it is a number (a result that is text, missing
  // or infinite has none).
  const std::string difference =
      std::isfinite(d) ? "difference " + format_number(d) + ", " : std::string();
  c.message = setting + ": " + cell_text(column) + " " +
              (got.empty() ? "missing" : cell_text(got)) + ", expected " + cell_text(want) + " (" +
              difference + "tolerance " + format_number(tolerance) + ": " + rule + ")";
  return c;
}

}  // namespace

namespace {

// The setting columns EXPECTED has and the quantities to compare, each
// checked to be in both files.
void choose_columns(const Table& results, const std::string& results_name, const Table& expected,
                    const std::string& expected_name, const CheckOptions& options,
                    std::vector<std::string>& keys, std::vector<std::string>& quantities) {
  quantities = options.columns;
  std::set<std::string> seen;
  for (const std::string& c : expected.rows[0]) {
    // A misspelt or repeated column would check nothing without a word.
    if (campaign_column_index(c) < 0) {
      throw_usage_error(shown(expected_name) + ": column '" + cell_text(c) +
                        "' is not a column of campaign results (docs/campaign.md)");
    }
    if (!seen.insert(c).second) {
      throw_usage_error(shown(expected_name) + ": column '" + cell_text(c) + "' appears twice");
    }
    if (is_setting(c)) keys.push_back(c);
    if (options.columns.empty() && compared_by_default(c)) quantities.push_back(c);
  }
  if (quantities.empty()) {
    throw_usage_error(shown(expected_name) +
                      " has no quantity to compare (rmse_mean, predicted_rmse, ...): the check "
                      "would check nothing");
  }
  if (keys.empty()) {
    std::string names;
    for (const char* k : kSettingColumns) names += (names.empty() ? "" : ", ") + std::string(k);
    throw_usage_error(shown(expected_name) + " has none of the setting columns (" + names +
                      "): nothing tells which result row each of its rows is");
  }
  for (const auto* list : {&keys, &quantities}) {
    for (const std::string& c : *list) {
      if (results.column.count(c) == 0 || expected.column.count(c) == 0) {
        throw_usage_error("column '" + cell_text(c) + "' is missing from " +
                          shown(results.column.count(c) != 0 ? expected_name : results_name));
      }
    }
  }
}

// "image=camera.png code=raskar ..." of expected row e.
std::string setting_label(const Table& expected, std::size_t e,
                          const std::vector<std::string>& keys) {
  std::string setting;
  for (const std::string& k : keys) {
    if (!setting.empty()) setting += ' ';
    setting += k;
    setting += '=';
    setting += cell_text(*expected.cell(e, k));
  }
  return setting;
}

// The result row with expected row e's settings; 0 when none. Refuses
// settings that match several result rows: the columns EXPECTED has do not
// tell them apart.
std::size_t matching_row(const Table& results, const std::string& results_name,
                         const Table& expected, std::size_t e,
                         const std::vector<std::string>& keys) {
  std::size_t found = 0;
  for (std::size_t r = 1; r < results.rows.size(); ++r) {
    const bool same = std::all_of(keys.begin(), keys.end(), [&](const std::string& k) {
      return same_setting_value(k, *results.cell(r, k), *expected.cell(e, k));
    });
    if (!same) continue;
    if (found != 0) {
      throw_usage_error(setting_label(expected, e, keys) + " matches lines " +
                        std::to_string(found + 1) + " and " + std::to_string(r + 1) + " of " +
                        shown(results_name) + ": give the setting columns that tell them apart");
    }
    found = r;
  }
  return found;
}

}  // namespace

CheckReport CheckCampaignResults(const std::string& results_csv, const std::string& results_name,
                                 const std::string& expected_csv, const std::string& expected_name,
                                 const CheckOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const Table results(results_csv, results_name), expected(expected_csv, expected_name);
  std::vector<std::string> keys, quantities;
  choose_columns(results, results_name, expected, expected_name, options, keys, quantities);
  const Comparison comparison{results, expected, options};
  CheckReport report;
  for (std::size_t e = 1; e < expected.rows.size(); ++e) {
    const std::string setting = setting_label(expected, e, keys);
    const std::size_t match = matching_row(results, results_name, expected, e, keys);
    if (match == 0) {
      std::string message = setting;
      message += ": no such row in ";
      message += shown(results_name);
      report.cases.push_back({setting, "", false, message});
      continue;
    }
    for (const std::string& q : quantities) {
      report.cases.push_back(comparison.compare(match, e, q, setting));
    }
  }
  return report;
}

CheckReport CheckCampaignResultFiles(const std::string& results_path,
                                     const std::string& expected_path,
                                     const CheckOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const std::string results =
      campaign_input::read_text_file(results_path, kMaxCheckFileBytes, "results file");
  const std::string expected =
      campaign_input::read_text_file(expected_path, kMaxCheckFileBytes, "expectations file");
  return CheckCampaignResults(results, results_path, expected, expected_path, options);
}

namespace {

// "line 3: code=raskar snr=200": the row's line and its setting columns whose values differ
// between rows of `t` (those that tell the rows apart).
std::string row_label(const Table& t, std::size_t row) {
  std::string label = "line " + std::to_string(row + 1) + ":";
  for (const char* key : kSettingColumns) {
    const auto it = t.column.find(key);
    if (it == t.column.end()) continue;
    const bool varies = std::any_of(t.rows.begin() + 1, t.rows.end(), [&](const auto& r) {
      return r[it->second] != t.rows[1][it->second];
    });
    if (varies) label += std::string(" ") + key + "=" + cell_text(t.rows[row][it->second]);
  }
  return label;
}

// Row `r`'s mean `measured` against its prediction `predicted`, the standard error from `sd` and
// the trials; nullopt when the row has none to compare (not ok, < 2 trials, no finite prediction).
std::optional<CheckCase> prediction_case(const Table& t, std::size_t r, const char* measured,
                                         const char* predicted, const char* sd,
                                         const CheckOptions& options) {
  const double n = number(*t.cell(r, "trials")), p = number(*t.cell(r, predicted));
  if (*t.cell(r, "status") != "ok" || !(n >= 2) || !std::isfinite(p)) return std::nullopt;
  const std::string& got = *t.cell(r, measured);
  const double m = number(got), se = number(*t.cell(r, sd)) / std::sqrt(n);
  if (std::isnan(m)) {  // no measured mean to compare: a deviation, without a difference
    return CheckCase{row_label(t, r), measured, false,
                     row_label(t, r) + " " + measured + " " +
                         (got.empty() ? "missing" : "'" + cell_text(got) + "'") + ", " + predicted +
                         " " + cell_text(*t.cell(r, predicted))};
  }
  const double d = m - p;
  const double k = options.k_standard_errors * se;
  const double tolerance =
      std::max({options.abs_tolerance, options.rel_tolerance * std::abs(p), std::isnan(k) ? 0 : k});
  CheckCase c{row_label(t, r), measured, std::abs(d) <= tolerance, ""};
  const std::string z = se > 0.0 ? ", z = " + format_number(d / se) : std::string();
  c.message = c.setting + " " + measured + " " + cell_text(*t.cell(r, measured)) + ", " +
              predicted + " " + cell_text(*t.cell(r, predicted)) + " (difference " +
              format_number(d) + z + "; tolerance " + format_number(tolerance) + ": abs " +
              format_exact(options.abs_tolerance) + ", rel " + format_exact(options.rel_tolerance) +
              ", " + format_exact(options.k_standard_errors) + " SE = " + format_number(k) + ")";
  return c;
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
  const Table t(results_csv, results_name);
  for (const char* c : {"status", "trials", "rmse_mean", "rmse_sd", "predicted_rmse"}) {
    if (t.column.count(c) == 0) {
      throw_usage_error(shown(results_name) + " has no column '" + c +
                        "': not the results.csv of a campaign");
    }
  }
  const bool distributions = t.column.count("velocity_distribution") != 0;
  for (const char* c : {"mse_mean", "mse_sd", "predicted_mse"}) {
    if (distributions && t.column.count(c) == 0) {
      throw_usage_error(shown(results_name) + " has velocity_distribution but no column '" + c +
                        "': not the results.csv of a campaign");
    }
  }
  CheckReport report;
  for (std::size_t r = 1; r < t.rows.size(); ++r) {
    // Under a distribution, sqrt(E[MSE]) is above the mean RMSE (Jensen): MSE is compared.
    const bool mse = distributions && !t.cell(r, "velocity_distribution")->empty();
    const std::optional<CheckCase> c =
        mse ? prediction_case(t, r, "mse_mean", "predicted_mse", "mse_sd", options)
            : prediction_case(t, r, "rmse_mean", "predicted_rmse", "rmse_sd", options);
    if (c) report.cases.push_back(*c);
  }
  if (report.cases.empty()) {
    throw_usage_error(shown(results_name) +
                      " has no row to compare with its prediction (status ok, 2 trials or more, "
                      "a finite prediction): the check would check nothing");
  }
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

namespace {

std::string xml_escape(const std::string& text) { return detail::escape_markup(text, false); }

}  // namespace

std::string check_junit_xml(const CheckReport& report, const std::string& suite_name) {
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuite name=\"" + xml_escape(suite_name) + "\" tests=\"" +
         std::to_string(report.cases.size()) + "\" failures=\"" +
         std::to_string(report.failures()) + "\">\n";
  for (const CheckCase& c : report.cases) {
    out += "  <testcase classname=\"" + xml_escape(c.setting) + "\" name=\"" +
           xml_escape(c.column.empty() ? "row" : c.column) + "\"";
    if (c.passed) {
      out += "/>\n";
    } else {
      out += ">\n    <failure message=\"" + xml_escape(c.message) + "\"/>\n  </testcase>\n";
    }
  }
  return out + "</testsuite>\n";
}

}  // namespace fss
