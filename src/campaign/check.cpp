#include "fss/campaign/check.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "campaign/check_table.h"
#include "campaign/column_roles.h"
#include "campaign/user_input.h"
#include "core/text_util.h"
#include "fss/campaign/results.h"
#include "fss/core/error.h"

namespace fss {

using check_table::cell_text;
using check_table::number;
using check_table::shown;
using check_table::Table;
using column_roles::Role;

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
    if (value && (!(*value >= 0.0) || !std::isfinite(*value))) {
      if (error)
        *error = std::string(name) + " = " + format_exact(*value) + ": must be finite and >= 0";
      return false;
    }
  }
  if (exact && (abs_tolerance || rel_tolerance)) {
    if (error) *error = "--exact compares numbers for equality: give it without --abs and --rel";
    return false;
  }
  return true;
}

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

Role role_of(const std::string& column) {
  const column_roles::ColumnRole* role = column_roles::find(column);
  return role != nullptr ? role->role : Role::kExact;
}

// The tolerances of a check (docs/campaign.md, "Regression checks"): a number passes within
// `abs`, `rel` times |expected| (kExactRelativeTolerance unless --rel or --exact is given) or,
// for a statistic, k standard errors: K of --k-se, or the default k when no tolerance is given.
struct Rules {
  double abs = 0.0;
  double rel = kExactRelativeTolerance;
  std::optional<double> k;  // --k-se K
  bool default_k = false;
  bool abs_or_rel = false;  // --abs or --rel given

  explicit Rules(const CheckOptions& o)
      : abs(o.abs_tolerance.value_or(0.0)),
        rel(o.rel_tolerance.value_or(o.exact ? 0.0 : kExactRelativeTolerance)),
        k(o.k_standard_errors),
        default_k(!o.abs_tolerance && !o.rel_tolerance && !o.k_standard_errors),
        abs_or_rel(o.abs_tolerance || o.rel_tolerance) {}
  bool standard_errors() const { return default_k || (k && *k > 0.0); }
};

// A quantity to compare.
struct Quantity {
  std::string name;
  std::string sd;       // its sd column, when its standard error is used
  bool fitted = false;  // set by the seed in the rows that fit to noise (column_roles)
  bool text = false;    // a text or boolean column: equal text
};

Quantity quantity_of(const std::string& name, const Rules& rules) {
  Quantity q;
  q.name = name;
  if (const column_roles::ColumnRole* role = column_roles::find(name)) {
    if (role->role == Role::kStatistic && rules.standard_errors()) q.sd = role->partner;
    q.fitted = role->fitted;
  }
  const int index = campaign_column_index(name);
  q.text = index >= 0 &&
           campaign_columns(true)[static_cast<std::size_t>(index)].kind != ColumnKind::kNumber;
  return q;
}

// The refusal of a k-SE rule that cannot apply: `where` (a file or a row of it) lacks `what`
// for statistic `q`.
[[noreturn]] void refuse_standard_error(const Rules& rules, const std::string& where,
                                        const Quantity& q, const std::string& what) {
  const std::string needs =
      q.sd + " and trials (" + std::to_string(kMinStandardErrorTrials) + " or more) in both files";
  if (rules.k) {
    throw_usage_error("--k-se " + format_exact(*rules.k) + ": " + where + " " + what +
                      ": the standard error of " + q.name + " needs " + needs +
                      "; give --abs or --rel instead");
  }
  throw_usage_error(where + " " + what + ": by default " + q.name +
                    " is compared within k standard errors, which need " + needs +
                    "; add them, or give --abs or --rel");
}

// The columns of the check: the settings that select the rows, the quantities, and the
// derived columns left out ("psnr_mean: follows rmse_mean").
struct Choice {
  std::vector<std::string> keys;
  std::vector<Quantity> quantities;
  std::vector<std::string> left_out;
};

// EXPECTED's header: each column a results column, once; its settings and, without
// options.columns, its statistics and exact outputs.
Choice columns_of_expected(const Table& expected, const std::string& expected_name,
                           const CheckOptions& options, const Rules& rules) {
  Choice choice;
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
    const Role role = role_of(c);
    if (role == Role::kSetting) choice.keys.push_back(c);
    if (!options.columns.empty()) continue;
    if (role == Role::kStatistic || role == Role::kExact) {
      choice.quantities.push_back(quantity_of(c, rules));
    } else if (role == Role::kDerived) {
      choice.left_out.push_back(c + ": follows " + std::string(column_roles::find(c)->partner));
    }
  }
  for (const std::string& c : options.columns) {
    const column_roles::ColumnRole* role = column_roles::find(c);
    if (role != nullptr && role->role == Role::kDerived && !rules.abs_or_rel) {
      throw_usage_error("--columns " + cell_text(c) + ": " + c + " follows " +
                        std::string(role->partner) +
                        " and has no standard error of its own; compare " +
                        std::string(role->partner) + ", or give --abs or --rel for " + c);
    }
    choice.quantities.push_back(quantity_of(c, rules));
  }
  return choice;
}

// The setting columns and quantities, each checked to be in both files, and the columns the
// k-SE rule needs.
Choice choose_columns(const Table& results, const std::string& results_name, const Table& expected,
                      const std::string& expected_name, const CheckOptions& options,
                      const Rules& rules) {
  Choice choice = columns_of_expected(expected, expected_name, options, rules);
  if (choice.quantities.empty()) {
    throw_usage_error(shown(expected_name) +
                      " has no quantity to compare (rmse_mean, predicted_rmse, ...; psnr_mean "
                      "follows rmse_mean): the check would check nothing");
  }
  if (choice.keys.empty()) {
    std::string names;
    for (const column_roles::ColumnRole& c : column_roles::all()) {
      if (c.role == Role::kSetting) names += (names.empty() ? "" : ", ") + std::string(c.name);
    }
    throw_usage_error(shown(expected_name) + " has none of the setting columns (" + names +
                      "): nothing tells which result row each of its rows is");
  }
  std::vector<std::string> needed = choice.keys;
  for (const Quantity& q : choice.quantities) needed.push_back(q.name);
  for (const std::string& c : needed) {
    if (!results.has(c) || !expected.has(c)) {
      throw_usage_error("column '" + cell_text(c) + "' is missing from " +
                        shown(results.has(c) ? expected_name : results_name));
    }
  }
  bool any = false;
  for (const Quantity& q : choice.quantities) {
    if (q.sd.empty()) continue;
    any = true;
    for (const auto& [table, name] :
         {std::pair{&expected, &expected_name}, std::pair{&results, &results_name}}) {
      for (const std::string& column : {q.sd, std::string("trials")}) {
        if (!table->has(column)) {
          refuse_standard_error(rules, shown(*name), q, "has no column '" + column + "'");
        }
      }
    }
  }
  if (!any && rules.k && *rules.k > 0.0) {
    throw_usage_error("--k-se " + format_exact(*rules.k) +
                      ": it applies to the means over the trials (rmse_mean, rmse_ci_mean, "
                      "ssim_mean, mse_mean), and none is compared");
  }
  return choice;
}

// The setting columns that name EXPECTED's rows: image and code, then those whose values differ
// between its rows (every one when it has a single row).
std::vector<std::string> label_keys(const Table& expected, const std::vector<std::string>& keys) {
  std::vector<std::string> shown_keys;
  for (const std::string& k : keys) {
    const int at = expected.column.at(k);
    const bool varies =
        expected.rows.size() <= 2 ||
        std::any_of(expected.rows.begin() + 1, expected.rows.end(),
                    [&](const auto& row) { return row[at] != expected.rows[1][at]; });
    if (k == "image" || k == "code" || varies) shown_keys.push_back(k);
  }
  return shown_keys;
}

// "image=camera.png code=raskar snr=100" of expected row e.
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
                         const Table& expected, std::size_t e, const std::vector<std::string>& keys,
                         const std::string& label) {
  std::size_t found = 0;
  for (std::size_t r = 1; r < results.rows.size(); ++r) {
    const bool same = std::all_of(keys.begin(), keys.end(), [&](const std::string& k) {
      return same_setting_value(k, *results.cell(r, k), *expected.cell(e, k));
    });
    if (!same) continue;
    if (found != 0) {
      throw_usage_error(shorten_for_message(label, 100) + " matches lines " +
                        std::to_string(found + 1) + " and " + std::to_string(r + 1) + " of " +
                        shown(results_name) + ": give the setting columns that tell them apart");
    }
    found = r;
  }
  return found;
}

// One comparison before its tolerance: expected row e, its result row r (0: none), quantity q,
// and, when the k-SE rule applies, the combined standard error and its degrees of freedom.
struct Pending {
  std::size_t e = 0, r = 0, q = 0;
  std::string label;
  double se = -1.0;  // sqrt(sd_r^2 / n_r + sd_e^2 / n_e); < 0 when not used
  double nu = 0.0;   // min(n_r, n_e) - 1
};

// sd^2 / n and n of quantity q in row `row` of `t` (the file `name`); refused unless both are
// numbers with n >= kMinStandardErrorTrials.
std::pair<double, double> mean_variance(const Table& t, const std::string& name, std::size_t row,
                                        const Quantity& q, const Rules& rules,
                                        const std::string& label) {
  const std::string& trials = *t.cell(row, "trials");
  const double sd = number(*t.cell(row, q.sd)), n = number(trials);
  std::string what;
  if (!(n >= kMinStandardErrorTrials) || std::isinf(n)) {
    what = std::isnan(n) ? "has no number in trials" : "has trials " + cell_text(trials);
  } else if (!(sd >= 0.0) || std::isinf(sd)) {
    what = "has no number in " + q.sd;
  }
  if (!what.empty()) {
    refuse_standard_error(rules,
                          "line " + std::to_string(row + 1) + " of " + shown(name) + " (" +
                              shorten_for_message(label, 100) + ")",
                          q, what);
  }
  return {sd * sd / n, n};
}

// Whether a fitted output of result row r is left out: the row fits to noise, neither --abs nor
// --rel is given, and the two files do not show the same seed for it.
bool fitted_left_out(const Table& results, std::size_t r, const Table& expected, std::size_t e,
                     const Rules& rules) {
  const std::string* restoration = results.cell(r, "restoration");
  const std::string* prior = results.cell(r, "prior");
  if (rules.abs_or_rel || restoration == nullptr || prior == nullptr ||
      !column_roles::fits_to_noise(*restoration, *prior)) {
    return false;
  }
  const std::string *seed_r = results.cell(r, "seed"), *seed_e = expected.cell(e, "seed");
  return seed_r == nullptr || seed_e == nullptr || *seed_r != *seed_e;
}

// The files' comparisons, in EXPECTED's order; *fitted_out counts the rows whose fitted outputs
// are left out.
std::vector<Pending> pending_comparisons(const Table& results, const std::string& results_name,
                                         const Table& expected, const std::string& expected_name,
                                         const Choice& choice, const Rules& rules,
                                         long long* fitted_out) {
  const std::vector<std::string> shown_keys = label_keys(expected, choice.keys);
  std::vector<Pending> pending;
  for (std::size_t e = 1; e < expected.rows.size(); ++e) {
    const std::string label = setting_label(expected, e, shown_keys);
    const std::size_t r = matching_row(results, results_name, expected, e, choice.keys, label);
    if (r == 0) {
      pending.push_back({e, 0, 0, label});
      continue;
    }
    const bool fitted_out_here = fitted_left_out(results, r, expected, e, rules);
    *fitted_out += fitted_out_here ? 1 : 0;
    for (std::size_t q = 0; q < choice.quantities.size(); ++q) {
      const Quantity& quantity = choice.quantities[q];
      if (quantity.fitted && fitted_out_here) continue;
      Pending p{e, r, q, label};
      if (!quantity.sd.empty() && std::isfinite(number(*expected.cell(e, quantity.name))) &&
          std::isfinite(number(*results.cell(r, quantity.name)))) {
        const auto [var_e, n_e] = mean_variance(expected, expected_name, e, quantity, rules, label);
        const auto [var_r, n_r] = mean_variance(results, results_name, r, quantity, rules, label);
        p.se = std::sqrt(var_r + var_e);
        p.nu = std::min(n_r, n_e) - 1.0;
      }
      pending.push_back(std::move(p));
    }
  }
  return pending;
}

// Comparison p with k standard errors (when its standard error is used).
CheckCase compare(const Table& results, const Table& expected, const Pending& p, const Quantity& q,
                  const Rules& rules, double k) {
  CheckCase c{p.label, q.name, false, ""};
  const std::string& got = *results.cell(p.r, q.name);
  const std::string& want = *expected.cell(p.e, q.name);
  const double g = number(got), w = number(want);
  if (std::isnan(w) || std::isinf(w)) {  // text, or a non-finite number: equal text
    c.passed = got == want;
    c.message = p.label + ": " + cell_text(q.name) + " is '" + cell_text(got) + "', expected '" +
                cell_text(want) + "'";
    return c;
  }
  const double d = g - w;
  double tolerance = std::max(rules.abs, rules.rel * std::abs(w));
  std::string rule = "abs " + format_exact(rules.abs) + ", rel " + format_exact(rules.rel);
  if (p.se >= 0.0) {
    tolerance = std::max(tolerance, k * p.se);
    rule += ", " + format_number(k, 4) + " SE = " + format_number(k * p.se);
  }
  c.passed = std::abs(d) <= tolerance;  // false for a missing or non-finite result
  // The difference only when it is a number (a result that is text, missing
  // or infinite has none).
  const std::string difference =
      std::isfinite(d) ? "difference " + format_number(d) + ", " : std::string();
  c.message = p.label + ": " + cell_text(q.name) + " " +
              (got.empty() ? "missing" : cell_text(got)) + ", expected " + cell_text(want) + " (" +
              difference + "tolerance " + format_number(tolerance) + ": " + rule + ")";
  return c;
}

// The summary lines: the quantities grouped by their tolerance, in EXPECTED's order, then
// what was left out.
std::vector<std::string> summary_of(const Choice& choice, const Rules& rules,
                                    const check_table::DefaultK& default_k, long long fitted_out) {
  const std::string k_text =
      rules.k ? format_exact(*rules.k) + " standard errors" : default_k.text();
  std::vector<std::pair<std::string, std::string>> groups;  // tolerance -> columns
  std::string fitted;
  for (const Quantity& q : choice.quantities) {
    const std::string tolerance =
        q.text ? "equal"
               : check_table::tolerance_text(rules.abs, rules.rel, q.sd.empty() ? "" : k_text);
    auto it = std::find_if(groups.begin(), groups.end(),
                           [&](const auto& g) { return g.first == tolerance; });
    if (it == groups.end()) it = groups.insert(groups.end(), {tolerance, ""});
    it->second += (it->second.empty() ? "" : ", ") + q.name;
    if (q.fitted) fitted += (fitted.empty() ? "" : ", ") + q.name;
  }
  // The statistics first, the text columns last.
  std::stable_partition(groups.begin(), groups.end(), [](const auto& g) {
    return g.first.find("standard errors") != std::string::npos;
  });
  std::stable_partition(groups.begin(), groups.end(),
                        [](const auto& g) { return g.first != "equal"; });
  std::vector<std::string> lines;
  for (const auto& [tolerance, columns] : groups) {
    lines.push_back("compared " + columns + ": " + tolerance);
  }
  for (const std::string& left : choice.left_out) lines.push_back("left out " + left);
  if (fitted_out > 0 && !fitted.empty()) {
    lines.push_back("left out " + fitted + " in " + std::to_string(fitted_out) +
                    " rows: Wiener's power-law prior is fitted to a noise draw, and the seeds "
                    "differ (--abs or --rel compares them)");
  }
  return lines;
}

}  // namespace

CheckReport CheckCampaignResults(const std::string& results_csv, const std::string& results_name,
                                 const std::string& expected_csv, const std::string& expected_name,
                                 const CheckOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(error);
  const Table results(results_csv, results_name), expected(expected_csv, expected_name);
  const Rules rules(options);
  const Choice choice =
      choose_columns(results, results_name, expected, expected_name, options, rules);
  long long fitted_out = 0;
  const std::vector<Pending> pending = pending_comparisons(
      results, results_name, expected, expected_name, choice, rules, &fitted_out);
  const auto with_se =
      std::count_if(pending.begin(), pending.end(), [](const Pending& p) { return p.se >= 0.0; });
  check_table::DefaultK default_k(with_se);
  CheckReport report;
  for (const Pending& p : pending) {
    if (p.r == 0) {
      report.cases.push_back(
          {p.label, "", false, p.label + ": no such row in " + shown(results_name)});
      continue;
    }
    const double k = p.se < 0.0 ? 0.0 : rules.k ? *rules.k : default_k.at(p.nu);
    report.cases.push_back(compare(results, expected, p, choice.quantities[p.q], rules, k));
  }
  report.summary = summary_of(choice, rules, default_k, fitted_out);
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

std::string xml_escape(const std::string& text) { return detail::escape_markup(text, false); }

}  // namespace

// One test case per comparison, named by its setting and quantity ("image=camera.png
// code=raskar snr=100: rmse_mean"), its class the suite and the quantity, so that a report
// groups the comparisons by quantity.
std::string check_junit_xml(const CheckReport& report, const std::string& suite_name) {
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuite name=\"" + xml_escape(suite_name) + "\" tests=\"" +
         std::to_string(report.cases.size()) + "\" failures=\"" +
         std::to_string(report.failures()) + "\">\n";
  for (const CheckCase& c : report.cases) {
    const std::string column = c.column.empty() ? "row" : c.column;
    out += "  <testcase classname=\"" + xml_escape(suite_name + "." + column) + "\" name=\"" +
           xml_escape(c.setting + ": " + column) + "\"";
    if (c.passed) {
      out += "/>\n";
    } else {
      out += ">\n    <failure message=\"" + xml_escape(c.message) + "\"/>\n  </testcase>\n";
    }
  }
  return out + "</testsuite>\n";
}

}  // namespace fss
