// Campaigns: fss.run_campaign and fss.read_campaign (docs/campaign.md; their docstrings:
// campaign_docs.h), through the library's fss/campaign/ as `fssim campaign` runs them.
#include <pybind11/pybind11.h>

#include <algorithm>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "arguments.h"
#include "bindings.h"
#include "campaign/user_input.h"
#include "campaign_columns.h"
#include "campaign_docs.h"
#include "convert.h"
#include "fss/campaign/check.h"
#include "fss/campaign/gaps.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"

namespace fss::python {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// The specification

// A value json.dumps does not know, as the JSON of a campaign file holds it: a path as its text,
// a numpy array as a list, a numpy scalar as the Python number or bool.
py::object json_value(const py::handle& value) {
  const py::module_ numpy = py::module_::import("numpy");
  if (py::hasattr(value, "__fspath__")) return py::module_::import("os").attr("fsdecode")(value);
  if (py::isinstance(value, numpy.attr("ndarray"))) return value.attr("tolist")();
  if (py::isinstance(value, numpy.attr("generic"))) return value.attr("item")();
  throw py::type_error(
      "spec: a value of type " +
      fss::shorten_for_message(py::type::of(value).attr("__name__").cast<std::string>()) +
      " is not a campaign field (numbers, strings, lists of them, paths)");
}

// A spec dict as the text of a campaign file.
std::string spec_json(const py::handle& spec) {
  const py::module_ json = py::module_::import("json");
  try {
    return json
        .attr("dumps")(py::dict(py::reinterpret_borrow<py::object>(spec)),
                       py::arg("default") = py::cpp_function(&json_value),
                       py::arg("allow_nan") = false)
        .cast<std::string>();
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ValueError)) throw;  // the TypeError of json_value, as it is
    throw py::value_error("spec: cannot be written as a campaign file's JSON (" +
                          fss::shorten_for_message(py::str(e.value()).cast<std::string>(), 120) +
                          ")");
  }
}

// A message of the campaign's checks with the fields named as the spec's keys: "campaign file
// 'spec': " as "spec: ", and `--velocity / "velocity"` as `velocity`.
std::string spec_words(const std::string& message) {
  static const std::regex kField(R"re(--[a-z-]+ / "([a-z_]+)")re");
  std::string text = std::regex_replace(message, kField, "$1");
  const std::string prefix = "campaign file 'spec': ";
  if (text.rfind(prefix, 0) == 0) text = "spec: " + text.substr(prefix.size());
  return text;
}

// The specification of `spec`, a dict of a campaign file's fields or a campaign file's path
// (`*file` receives the path: an input, never written over); read and resolved (the images read,
// the codes loaded), with per_trial= over its field when given.
fss::ResolvedCampaign resolved_spec(const py::object& spec, const py::object& per_trial,
                                    std::string* file) {
  fss::CampaignSpec parsed;
  const bool mapping = py::isinstance(spec, py::module_::import("collections.abc").attr("Mapping"));
  try {
    if (mapping) {
      parsed = fss::parse_campaign_file(spec_json(spec), "spec");
    } else if (py::isinstance<py::str>(spec) || py::isinstance<py::bytes>(spec) ||
               py::hasattr(spec, "__fspath__")) {
      *file = path_argument(spec, "spec");
      py::gil_scoped_release release;
      parsed = fss::read_campaign_file(*file);
    } else {
      throw_type_error("spec", "a dict or the path of a campaign file", spec);
    }
    if (!per_trial.is_none()) parsed.per_trial = bool_argument(per_trial, "per_trial");
    py::gil_scoped_release release;
    return fss::resolve_campaign(parsed);
  } catch (const fss::Error& e) {
    throw fss::Error(e.kind(), spec_words(e.what()));
  }
}

// ---------------------------------------------------------------------------
// run_campaign

// Ctrl-C while the campaign runs without the GIL: the next setting's end raises the
// KeyboardInterrupt (the journal keeps every setting that ended; a rerun resumes).
void check_signals(const fss::CampaignProgress&) {
  py::gil_scoped_acquire acquire;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

fss::CampaignRunOptions run_options(const py::object& threads, const py::object& max_memory,
                                    const std::string& file) {
  fss::CampaignRunOptions options;
  const long long count = int_argument(threads, "threads");
  if (const std::string rule = fss::threads_rule(count); !rule.empty()) {
    throw py::value_error("threads = " + std::to_string(count) + ": " + rule);
  }
  options.threads = fss::python::int_argument("threads", count, 0, INT_MAX);
  const std::uint64_t limit = uint64_argument(max_memory, "max_memory", " (bytes; 0: no limit)");
  options.max_memory_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(limit, SIZE_MAX));
  options.fssim_version = FSS_VERSION_FULL;
  if (!file.empty()) options.inputs.push_back(file);
  options.progress = check_signals;
  return options;
}

// fssim's list of the settings that did not run (gap_report_lines: headings ending in ':', each
// followed by its indented items) on one line: "4 of 4 settings cannot run (...): reason: code=a
// velocity=1; code=b velocity=1".
std::string gap_text(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) {
    const std::size_t start = line.find_first_not_of(' ');
    if (start == std::string::npos) continue;
    if (!text.empty()) text += text.back() == ':' ? " " : "; ";
    text += line.substr(start);
  }
  return text;
}

// The settings that did not run: when some cannot run and skip_unrunnable is False, the
// RuntimeError of fssim's exit status 1; else one warning listing them, as fssim's stderr.
void report_gaps(const fss::ResolvedCampaign& campaign, const std::vector<fss::ResultRow>& rows,
                 const std::string& outdir, bool skip_unrunnable) {
  const std::vector<fss::CampaignGap> gaps =
      fss::campaign_gaps(rows, campaign.has_velocity_distributions());
  const std::string text =
      gap_text(fss::gap_report_lines(gaps, static_cast<long long>(rows.size())));
  const long long cannot_run = fss::count_gaps(gaps, fss::GapKind::kCannotRun);
  if (cannot_run == 0 || skip_unrunnable) {
    if (!text.empty()) warn(text);
    return;
  }
  const std::string dir = "'" + fss::shorten_for_message(outdir, 80) + "'";
  fss::throw_runtime_error(std::to_string(cannot_run) +
                           (cannot_run == 1 ? " setting cannot run" : " settings cannot run") +
                           " (the results of the others are written; "
                           "fss.read_campaign(" +
                           dir +
                           ") reads them, their status and message say why): change those "
                           "settings or give skip_unrunnable=True");
}

py::dict run_campaign(const py::object& spec, const py::object& outdir_object,
                      const py::object& threads, const py::object& skip_unrunnable,
                      const py::object& per_trial, const py::object& max_memory) {
  const std::string outdir = path_argument(outdir_object, "outdir");
  const bool skip = bool_argument(skip_unrunnable, "skip_unrunnable");
  std::string file;
  const fss::ResolvedCampaign campaign = resolved_spec(spec, per_trial, &file);
  const fss::CampaignRunOptions options = run_options(threads, max_memory, file);
  fss::CampaignRunSummary summary;
  {
    py::gil_scoped_release release;
    summary = fss::RunCampaign(campaign, outdir, options);
  }
  report_gaps(campaign, summary.rows, outdir, skip);
  std::vector<std::string> names;
  for (const fss::ResultColumn& column :
       fss::campaign_columns(campaign.has_velocity_distributions())) {
    names.emplace_back(column.name);
  }
  return campaign_columns_dict(names, summary.rows,
                               (fs::path(outdir) / fss::kCampaignResultsCsv).string());
}

// ---------------------------------------------------------------------------
// read_campaign

// The file read_campaign reads: a campaign directory's results.csv (trials.csv with `trials`),
// or the file given.
std::string campaign_file(const std::string& path, bool trials) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return path;
  const fs::path file =
      fs::path(path) / (trials ? fss::kCampaignTrialsCsv : fss::kCampaignResultsCsv);
  if (trials && !fs::exists(file, ec) &&
      fs::exists(fs::path(path) / fss::kCampaignResultsCsv, ec)) {
    fss::throw_runtime_error("campaign '" + fss::escape_control_characters(path) +
                             "' has no trials.csv: run it with per_trial=True (or \"per_trial\": "
                             "true in its spec)");
  }
  return file.string();
}

py::dict read_campaign(const py::object& path_object, const py::object& trials_object) {
  const std::string path = path_argument(path_object, "path");
  const bool trials = bool_argument(trials_object, "trials");
  const std::string file = campaign_file(path, trials);
  std::vector<std::vector<std::string>> rows;
  {
    py::gil_scoped_release release;
    const std::string text =
        fss::campaign_input::read_text_file(file, fss::kMaxCheckFileBytes, "results file");
    try {
      rows = fss::parse_csv(text, file);
    } catch (const fss::Error& e) {
      fss::throw_runtime_error(e.what());  // a file's content, not an argument
    }
  }
  if (rows.empty()) {
    fss::throw_runtime_error("results file '" + fss::escape_control_characters(file) +
                             "' is empty (expected a header line)");
  }
  const std::vector<std::string> names = rows.front();
  const bool trial_file = std::find(names.begin(), names.end(), "trial") != names.end();
  if (trials && !trial_file) {
    throw py::value_error("trials=True: '" + fss::escape_control_characters(file) +
                          "' is not a trials.csv (give the campaign directory or its trials.csv)");
  }
  rows.erase(rows.begin());
  return campaign_columns_dict(names, rows, file);
}

}  // namespace

void define_campaigns(py::module_& m) {
  m.def("run_campaign", &run_campaign, py::arg("spec"), py::arg("outdir"), py::kw_only(),
        py::arg("threads") = 0, py::arg("skip_unrunnable") = false,
        py::arg("per_trial") = py::none(), py::arg("max_memory") = 0, kRunCampaignDoc);
  m.def("read_campaign", &read_campaign, py::arg("path"), py::kw_only(), py::arg("trials") = false,
        kReadCampaignDoc);
}

}  // namespace fss::python
