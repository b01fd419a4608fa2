#include "campaign/check_table.h"

#include <cmath>
#include <cstdlib>

#include "campaign/student_t.h"
#include "fss/campaign/check.h"
#include "fss/core/error.h"

namespace fss::check_table {

std::string shown(const std::string& name) {
  std::string text = "'";
  text += escape_control_characters(name);
  return text + "'";
}

std::string cell_text(const std::string& text) { return shorten_for_message(text, 80); }

double number(const std::string& text) {
  if (text.empty()) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() ? v : std::nan("");
}

Table::Table(const std::string& text, const std::string& name) : rows(parse_csv(text, name)) {
  for (std::size_t i = 0; i < rows[0].size(); ++i) column[rows[0][i]] = static_cast<int>(i);
}

const std::string* Table::cell(std::size_t row, const std::string& name) const {
  const auto it = column.find(name);
  return it == column.end() ? nullptr : &rows[row][static_cast<std::size_t>(it->second)];
}

DefaultK::DefaultK(long long comparisons) : comparisons_(comparisons < 1 ? 1 : comparisons) {}

// k with P(|T_nu| > k) = alpha / N: the chance that any of the N comparisons of a check exceeds
// its k by chance alone is at most alpha (Bonferroni, whatever their correlation).
double DefaultK::at(double degrees_of_freedom) {
  const auto [it, added] = k_.try_emplace(degrees_of_freedom, 0.0);
  if (added) {
    it->second = student_t::two_sided_quantile(
        kCheckFalseAlarmRate / static_cast<double>(comparisons_), degrees_of_freedom);
  }
  return it->second;
}

std::string DefaultK::text() const {
  if (k_.empty()) return "k standard errors";
  // k decreases as the degrees of freedom grow.
  const auto& [nu_low, k_high] = *k_.begin();
  const auto& [nu_high, k_low] = *k_.rbegin();
  const auto range = [](double low, double high, int digits) {
    const std::string a = format_number(low, digits), b = format_number(high, digits);
    return a == b ? a : a + " to " + b;
  };
  return "k = " + range(k_low, k_high, 3) + " standard errors (Student-t, " +
         range(nu_low, nu_high, 6) + " degrees of freedom: a false alarm among these " +
         std::to_string(comparisons_) + " comparisons has a chance below " +
         format_number(100.0 * kCheckFalseAlarmRate, 3) + " %)";
}

std::string tolerance_text(double abs, double rel, const std::string& k_text) {
  std::string text;
  const auto add = [&text](const std::string& part) {
    text += (text.empty() ? "within " : ", or ") + part;
  };
  if (!k_text.empty()) add(k_text);
  if (abs > 0.0) add("abs " + format_exact(abs));
  if (rel > 0.0) add("rel " + format_exact(rel));
  return text.empty() ? "equal" : text;
}

}  // namespace fss::check_table
