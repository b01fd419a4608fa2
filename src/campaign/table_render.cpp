// The text of a campaign table in each format (table_model.h).
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "campaign/table_model.h"
#include "fss/core/error.h"

namespace fss::table_model {

namespace {

using table_numbers::Rounded;

// The header of a column: a short name for the quantities a paper reports,
// the results column's name for the rest.
std::string label(const std::string& column) {
  static const std::map<std::string, std::string> labels = {
      {"rmse_mean", "RMSE"},
      {"rmse_ci_mean", "RMSE_CI"},
      {"mse_mean", "MSE"},
      {"ssim_mean", "SSIM"},
      {"psnr_mean", "PSNR (dB)"},
      {"predicted_rmse", "predicted RMSE"},
      {"predicted_mse", "predicted MSE"},
      {"predicted_rmse_noise_free", "noise-free RMSE"},
  };
  const auto it = labels.find(column);
  return it == labels.end() ? column : it->second;
}

// CSV: the standard error's column of a statistic, rmse_mean -> rmse_se.
std::string se_column(const std::string& column) {
  const std::string stem = column.ends_with("_mean") ? column.substr(0, column.size() - 5) : column;
  return stem + "_se";
}

std::string markdown_text(const std::string& text) {
  std::string out;
  for (const char c : escape_control_characters(text)) {
    if (std::string_view("\\`*_|<>[]~").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string latex_text(const std::string& text) {
  static const std::map<char, std::string> words = {
      {'\\', "\\textbackslash{}"}, {'~', "\\textasciitilde{}"}, {'^', "\\textasciicircum{}"},
      {'|', "\\textbar{}"},        {'<', "\\textless{}"},       {'>', "\\textgreater{}"}};
  std::string out;
  for (const char c : escape_control_characters(text)) {
    if (const auto it = words.find(c); it != words.end()) {
      out += it->second;
      continue;
    }
    if (std::string_view("#$%&_{}").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

// RFC 4180: quoted when it holds a comma, a quote or a line break.
std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// 10 to the power `exponent` in Unicode superscripts: "10⁻⁵".
std::string superscript_power(int exponent) {
  static const char* const digits[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string out = exponent < 0 ? "10⁻" : "10";
  for (const char c : std::to_string(exponent < 0 ? -exponent : exponent)) out += digits[c - '0'];
  return out;
}

std::string markdown_number(const Rounded& n) {
  if (n.mantissa == "inf") return "∞";
  if (n.mantissa == "-inf") return "-∞";
  return n.exponent == 0 ? n.mantissa : n.mantissa + " × " + superscript_power(n.exponent);
}

std::string latex_number(const Rounded& n) {
  if (n.mantissa == "inf") return "$\\infty$";
  if (n.mantissa == "-inf") return "$-\\infty$";
  if (n.exponent == 0) return "$" + n.mantissa + "$";
  return "$" + n.mantissa + " \\times 10^{" + std::to_string(n.exponent) + "}$";
}

std::string csv_number(const Rounded& n) {
  return n.exponent == 0 ? n.mantissa : n.mantissa + "e" + std::to_string(n.exponent);
}

std::string markdown_cell(const Cell& cell) {
  switch (cell.kind) {
    case Cell::Kind::kEmpty:
      return "—";
    case Cell::Kind::kText:
      return markdown_text(cell.text);
    case Cell::Kind::kNumber:
      return markdown_number(cell.value);
    case Cell::Kind::kMeanSe:
      break;
  }
  const std::string pair = cell.value.mantissa + " ± " + cell.se.mantissa;
  return cell.value.exponent == 0 ? pair
                                  : "(" + pair + ") × " + superscript_power(cell.value.exponent);
}

std::string latex_cell(const Cell& cell) {
  switch (cell.kind) {
    case Cell::Kind::kEmpty:
      return "---";
    case Cell::Kind::kText:
      return latex_text(cell.text);
    case Cell::Kind::kNumber:
      return latex_number(cell.value);
    case Cell::Kind::kMeanSe:
      break;
  }
  const std::string pair = cell.value.mantissa + " \\pm " + cell.se.mantissa;
  if (cell.value.exponent == 0) return "$" + pair + "$";
  return "$(" + pair + ") \\times 10^{" + std::to_string(cell.value.exponent) + "}$";
}

// Whether column `column` (every column when npos) has a cell mean ± SE.
bool has_standard_errors(const Table& table, std::size_t column = std::string::npos) {
  for (const std::vector<Cell>& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if ((column == std::string::npos || i == column) && row[i].kind == Cell::Kind::kMeanSe) {
        return true;
      }
    }
  }
  return false;
}

// The header of column i: its label, "(mean ± SE)" after a statistic shown so.
std::string header(const Table& table, std::size_t i, TableFormat format) {
  const bool latex = format == TableFormat::kLatex;
  const std::string name = label(table.columns[i].name);
  std::string text = latex ? latex_text(name) : markdown_text(name);
  if (!has_standard_errors(table, i)) return text;
  return text + (latex ? " (mean $\\pm$ SE)" : " (mean ± SE)");
}

// The caption: the fixed settings, the trials and what mean ± SE stands for,
// as one sentence; empty when there is nothing to say.
std::string caption(const Table& table, TableFormat format) {
  const bool latex = format == TableFormat::kLatex;
  const auto text = [latex](const std::string& s) {
    return latex ? latex_text(s) : markdown_text(s);
  };
  std::vector<std::string> parts;
  if (!table.fixed.empty()) {
    std::string fixed = "Fixed settings: ";
    for (std::size_t i = 0; i < table.fixed.size(); ++i) {
      fixed +=
          (i > 0 ? ", " : "") + text(table.fixed[i].first) + " = " + text(table.fixed[i].second);
    }
    parts.push_back(fixed);
  }
  if (!table.trials.empty()) {
    parts.push_back(text(table.trials) + (table.trials == "1" ? " trial" : " trials") +
                    " a setting");
  }
  if (has_standard_errors(table)) {
    parts.push_back(latex ? "mean $\\pm$ standard error (SE: sample sd$/\\sqrt{\\mathrm{trials}}$)"
                          : "mean ± standard error (SE: sample sd / √trials)");
  }
  std::string sentence;
  for (std::size_t i = 0; i < parts.size(); ++i) sentence += (i > 0 ? "; " : "") + parts[i];
  if (sentence.empty()) return sentence;
  if (sentence[0] >= 'a' && sentence[0] <= 'z') sentence[0] = static_cast<char>(sentence[0] - 32);
  return sentence + ".";
}

std::string markdown(const Table& table) {
  std::string out = caption(table, TableFormat::kMarkdown);
  if (!out.empty()) out += "\n\n";
  std::string rule = "|";
  out += "|";
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    out += " " + header(table, i, TableFormat::kMarkdown) + " |";
    rule += table.columns[i].number ? "---:|" : "---|";
  }
  out += "\n" + rule + "\n";
  for (const std::vector<Cell>& row : table.rows) {
    out += "|";
    for (const Cell& cell : row) out += " " + markdown_cell(cell) + " |";
    out += "\n";
  }
  return out;
}

std::string latex(const Table& table) {
  std::string out = "% fssim campaign table: a booktabs tabular (\\usepackage{booktabs})\n";
  if (const std::string c = caption(table, TableFormat::kLatex); !c.empty()) out += "% " + c + "\n";
  std::string spec, headers;
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    spec += table.columns[i].number ? 'r' : 'l';
    headers += (i > 0 ? " & " : "") + header(table, i, TableFormat::kLatex);
  }
  out += "\\begin{tabular}{" + spec + "}\n\\toprule\n" + headers + " \\\\\n\\midrule\n";
  for (const std::vector<Cell>& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) out += (i > 0 ? " & " : "") + latex_cell(row[i]);
    out += " \\\\\n";
  }
  return out + "\\bottomrule\n\\end{tabular}\n";
}

// The CSV fields of a cell: its value, and its standard error after it in a
// statistic's column.
void append_csv_fields(const Cell& cell, bool statistic, std::vector<std::string>& fields) {
  fields.push_back(cell.kind == Cell::Kind::kText    ? csv_text(cell.text)
                   : cell.kind == Cell::Kind::kEmpty ? std::string()
                                                     : csv_number(cell.value));
  if (statistic) {
    fields.push_back(cell.kind == Cell::Kind::kMeanSe ? csv_number(cell.se) : std::string());
  }
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) line += ',';
    line += fields[i];
  }
  return line + "\n";
}

// CSV: a statistic is two columns, its mean and its standard error.
std::string csv(const Table& table) {
  std::vector<std::string> header;
  for (const Column& column : table.columns) {
    header.push_back(column.name);
    if (column.statistic) header.push_back(se_column(column.name));
  }
  std::string out = csv_line(header);
  for (const std::vector<Cell>& row : table.rows) {
    std::vector<std::string> fields;
    for (std::size_t i = 0; i < row.size(); ++i) {
      append_csv_fields(row[i], table.columns[i].statistic, fields);
    }
    out += csv_line(fields);
  }
  return out;
}

}  // namespace

std::string render(const Table& table, TableFormat format) {
  switch (format) {
    case TableFormat::kLatex:
      return latex(table);
    case TableFormat::kCsv:
      return csv(table);
    case TableFormat::kMarkdown:
      break;
  }
  return markdown(table);
}

}  // namespace fss::table_model
