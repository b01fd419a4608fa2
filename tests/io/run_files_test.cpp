// Tests of the table of a run's files (run_files.h): it is consistent, it
// drives output_file_names and report.html's figures, and the "Outputs"
// table of docs/cli.md lists the same files under the same conditions.
#include "io/run_files.h"

#include <gtest/gtest.h>

#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fss/io/outputs.h"
#include "io/html_report.h"
#include "support/test_util.h"

namespace fss {

// Readable conditions in failure messages.
void PrintTo(RunFileCondition when, std::ostream* out) {
  constexpr const char* kNames[] = {"always", "plots", "sheet", "html_report"};
  *out << kNames[static_cast<int>(when)];
}

namespace {

using enum RunFileCondition;

// (name, condition) of every row, in order.
std::vector<std::pair<std::string, RunFileCondition>> table_rows() {
  std::vector<std::pair<std::string, RunFileCondition>> rows;
  for (const RunFile& file : run_files()) rows.emplace_back(file.name, file.when);
  return rows;
}

// How docs/cli.md says when a file is written, at the end of its content.
RunFileCondition documented_condition(const std::string& content) {
  const std::vector<std::pair<std::string, RunFileCondition>> markers = {
      {"(not with `--no-plots`)", kPlots},
      {"(`--sheet`)", kSheet},
      {"(`--report`)", kHtmlReport},
      {"(`--save-float`)", kFloat}};
  RunFileCondition found = kAlways;
  int count = 0;
  for (const auto& [marker, condition] : markers) {
    if (content.find(marker) != std::string::npos) {
      found = condition;
      ++count;
    }
  }
  EXPECT_LE(count, 1) << "more than one condition in: " << content;
  return found;
}

// (name, condition) of every row of the table under the "## Outputs"
// heading of docs/cli.md, in order.
std::vector<std::pair<std::string, RunFileCondition>> documented_rows() {
  std::vector<std::pair<std::string, RunFileCondition>> rows;
  bool in_section = false;
  const std::string cli_docs = test::read_file(test::source_path("docs/cli.md"));
  for (const std::string& line : test::lines_of(cli_docs)) {
    if (line.rfind("## ", 0) == 0) in_section = line == "## Outputs";
    if (!in_section || line.rfind("| `", 0) != 0) continue;
    const std::size_t name_end = line.find('`', 3);
    const std::size_t content = line.find('|', name_end);
    if (name_end == std::string::npos || content == std::string::npos) {
      ADD_FAILURE() << "cannot read the docs/cli.md row: " << line;
      continue;
    }
    rows.emplace_back(line.substr(3, name_end - 3), documented_condition(line.substr(content)));
  }
  return rows;
}

// The names of the table's rows written under these options, in order.
std::vector<std::string> names_written(bool plots, bool sheet, bool html, bool floats) {
  std::vector<std::string> names;
  for (const auto& [name, when] : table_rows()) {
    if (when == kAlways || (when == kPlots && plots) || (when == kSheet && sheet) ||
        (when == kHtmlReport && html) || (when == kFloat && floats)) {
      names.push_back(name);
    }
  }
  return names;
}

TEST(RunFiles, RowsAreCompleteAndNamesUnique) {
  std::set<std::string> names;
  for (const RunFile& file : run_files()) {
    SCOPED_TRACE(file.name);
    EXPECT_TRUE(names.insert(file.name).second) << "listed twice";
    EXPECT_NE(file.make, nullptr);
    EXPECT_NE(std::string(file.content), "");
    EXPECT_EQ(std::string(file.caption).empty(), file.figure == RunFileFigure::kNone);
  }
}

TEST(RunFiles, TheCliDocsListTheSameFilesUnderTheSameConditions) {
  EXPECT_EQ(documented_rows(), table_rows());
}

TEST(RunFiles, OutputFileNamesAreTheRowsTheOptionsSelectInOrder) {
  EXPECT_EQ(output_file_names({true, true, true}),
            (std::vector<std::string>{"observed.png", "restored.png", "groundtruth.png",
                                      "residual.png", "code.txt", "spectrum.txt", "report.json",
                                      "code.png", "spectrum.png", "sheet.png", "report.html"}));
  OutputOptions floats;
  floats.float_outputs = true;
  EXPECT_EQ(
      output_file_names(floats),
      (std::vector<std::string>{"observed.png", "restored.png", "groundtruth.png", "residual.png",
                                "observed.tif", "restored.tif", "residual.tif", "code.txt",
                                "spectrum.txt", "report.json", "code.png", "spectrum.png"}));
  for (const bool plots : {false, true}) {
    for (const bool sheet : {false, true}) {
      for (const bool html : {false, true}) {
        for (const bool float_outputs : {false, true}) {
          EXPECT_EQ(output_file_names({plots, sheet, html, float_outputs}),
                    names_written(plots, sheet, html, float_outputs))
              << plots << sheet << html << float_outputs;
        }
      }
    }
  }
}

TEST(RunFiles, ReportFiguresAreTheFigureRows) {
  std::vector<std::string> figures;
  for (const RunFile& file : run_files()) {
    if (file.figure != RunFileFigure::kNone) figures.emplace_back(file.name);
  }
  std::vector<std::string> shown;
  for (const ReportFigure& figure : report_figures()) shown.emplace_back(figure.file);
  EXPECT_EQ(shown, figures);
  EXPECT_EQ(shown, (std::vector<std::string>{"observed.png", "restored.png", "groundtruth.png",
                                             "residual.png", "code.png", "spectrum.png"}));
}

}  // namespace
}  // namespace fss
