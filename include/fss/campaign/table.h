// A campaign's results as a table for a paper (docs/campaign.md, "Tables"):
// the settings that vary, each measured mean with its standard error, the
// predictions, in Markdown, LaTeX (booktabs) or CSV.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fss {

enum class TableFormat { kMarkdown, kLatex, kCsv };

// "markdown", "latex", "csv"; nullopt for any other text.
std::optional<TableFormat> table_format_from_string(std::string_view text);

// Significant digits of a standard error (and decimals of its mean) a table
// may ask for.
inline constexpr int kMinTableDigits = 1;
inline constexpr int kMaxTableDigits = 6;

struct TableOptions {
  TableFormat format = TableFormat::kMarkdown;
  // Columns of results.csv to show, in order; empty: the setting columns whose
  // value differs between rows, then rmse_mean, predicted_rmse and rmse_ci_mean
  // (under velocity distributions mse_mean, predicted_mse and rmse_ci_mean).
  std::vector<std::string> columns;
  int digits = 2;  // significant digits of each standard error

  // False with a message naming the field when digits is out of [kMinTableDigits,
  // kMaxTableDigits].
  bool IsValid(std::string* error) const;
};

// The table of RESULTS (the text of a campaign's results.csv, named
// `results_name` in messages). Throws a usage fss::Error, one line, for
// malformed CSV, a file without rows or without the columns of a results.csv
// (status, trials), a column that is not a results column or that the file
// lacks, a column asked twice, and invalid options.
std::string campaign_table(const std::string& results_csv, const std::string& results_name,
                           const TableOptions& options);

// campaign_table of the file at `results_path`, read bounded by
// kMaxCheckFileBytes (fss/campaign/check.h; a runtime fss::Error naming the
// file when larger or unreadable).
std::string campaign_table_file(const std::string& results_path, const TableOptions& options);

}  // namespace fss
