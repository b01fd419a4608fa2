#include "campaign_command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_common.h"
#include "fss/campaign/check.h"
#include "fss/campaign/figures.h"
#include "fss/campaign/gaps.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/campaign/table.h"
#include "fss/core/error.h"
#include "fss/model/code.h"
#include "io/safe_write.h"

namespace fssim {

namespace {

namespace fs = std::filesystem;

std::string shown_path(const std::string& path) {
  return "'" + fss::escape_control_characters(path) + "'";
}

// Refuses (a usage error) output `output`, named `what`, when it is the
// same file as one of `inputs` (device and inode; a path that does not
// exist yet is no input).
void refuse_output_over_inputs(const std::string& what, const std::string& output,
                               const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    if (fss::same_file(output, input)) {
      fss::throw_usage_error(what + " " + shown_path(output) + " would replace the input " +
                             shown_path(input) + "; choose another path");
    }
  }
}

// The files a campaign reads: the campaign file (if any), its images, its
// code files and its velocity files.
std::vector<std::string> campaign_inputs(const std::string& file,
                                         const fss::ResolvedCampaign& campaign) {
  std::vector<std::string> inputs;
  if (!file.empty()) inputs.push_back(file);
  for (const fss::CampaignImage& image : campaign.images) inputs.push_back(image.path);
  for (const fss::CampaignCode& code : campaign.codes) {
    if (!fss::builtin_code(code.name)) inputs.push_back(code.name);
  }
  for (const fss::CampaignDistribution& d : campaign.velocity_distributions) {
    if (d.distribution.kind == fss::VelocityDistributionKind::kDiscrete) inputs.push_back(d.name);
  }
  return inputs;
}

// Refuses, before anything runs, an input inside DIR/figures, where
// --figures writes.
void refuse_inputs_among_figures(const std::string& dir, const std::vector<std::string>& inputs) {
  const fs::path figures = fs::path(dir) / "figures";
  for (const std::string& input : inputs) {
    const fs::path parent = fs::path(input).parent_path();
    if (fss::same_file(parent.empty() ? fs::path(".") : parent, figures)) {
      fss::throw_usage_error("the input " + shown_path(input) + " is in " +
                             shown_path(figures.string()) +
                             ", where --figures writes; choose another output directory");
    }
  }
}

std::vector<fss::ShutterMode> parse_modes(const std::vector<std::string>& names) {
  std::vector<fss::ShutterMode> modes;
  for (const std::string& name : names) {
    const auto mode = fss::shutter_mode_from_string(name);
    if (!mode) fss::throw_usage_error("--mode '" + name + "': expected numerical or analog");
    modes.push_back(*mode);
  }
  return modes;
}

fss::NoiseModel parse_noise(const std::string& name) {
  const auto noise = fss::noise_model_from_string(name);
  if (!noise) fss::throw_usage_error("--noise '" + name + "': not a noise model of fssim");
  return *noise;
}

// "campaign: 12/40 settings, 3.1/s, ETA 9 s" over itself on a terminal.
void print_progress(const fss::CampaignProgress& p) {
  const long long ran = p.done - p.resumed;
  const double rate = p.elapsed_s > 0.0 ? ran / p.elapsed_s : 0.0;
  std::string eta = "--";
  if (rate > 0.0) eta = format_number(std::ceil((p.total - p.done) / rate), 6) + " s";
  std::fprintf(stderr, "\rcampaign: %lld/%lld settings, %.3g/s, ETA %s   ", p.done, p.total, rate,
               eta.c_str());
  if (p.done == p.total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace

CampaignCommand::CampaignCommand(CLI::App& parent)
    : Command(parent, "campaign",
              "run images x codes x settings into a directory of tidy results (results.csv, "
              "results.jsonl), resumably and in shards; see docs/campaign.md") {
  app().require_subcommand(0, 1);
  AddSpecOptions();
  merge_ = app().add_subcommand(
      "merge", "merge the directories of the shards 1/N .. N/N of one campaign into DIR");
  merge_->add_option("-o,--output", merge_output_, "directory of the merged results")
      ->required()
      ->check(not_empty());
  merge_->add_option("parts", parts_, "the shards' directories")->required();
  merge_->add_flag("--figures", merge_figures_, "also draw the figures into DIR/figures");
  merge_->add_flag("--skip-unrunnable", merge_skip_unrunnable_,
                   "exit 0 even when some settings cannot run (they are listed on stderr and "
                   "marked in results.csv)");
  check_ = app().add_subcommand(
      "check",
      "compare RESULTS.csv with EXPECTED.csv (or with its own predictions: --predicted); exit 1 "
      "on a deviation or a missing row");
  check_->add_option("results", results_, "results.csv of a campaign")->required();
  check_->add_option("expected", expected_,
                     "expected values, columns named as results.csv's (not with --predicted)");
  check_->add_flag("--predicted", predicted_,
                   "compare each row's mean with its own prediction within k standard errors: "
                   "mse_mean with predicted_mse under a velocity distribution, else rmse_mean "
                   "with predicted_rmse");
  check_
      ->add_option("--columns", check_columns_,
                   "quantities to compare (default: the means and exact outputs EXPECTED has)")
      ->delimiter(',');
  check_->add_option("--abs", abs_tolerance_, "absolute tolerance")->check(CLI::NonNegativeNumber);
  check_->add_option("--rel", rel_tolerance_, "relative tolerance (default 1e-9)")
      ->check(CLI::NonNegativeNumber);
  check_
      ->add_option("--k-se", k_se_,
                   "tolerance in standard errors of the means (default: Student-t k, 0.1 % false "
                   "alarms per check; none with --abs or --rel)")
      ->check(CLI::NonNegativeNumber);
  check_->add_flag("--exact", exact_,
                   "numbers equal, without the relative 1e-9 (the means still within k standard "
                   "errors; not with --abs, --rel)");
  check_->add_option("--junit", junit_, "also write a JUnit XML report to FILE");
  AddTableCommand();
}

void CampaignCommand::AddTableCommand() {
  table_ = app().add_subcommand(
      "table",
      "print RESULTS.csv as a table for a paper: the settings that vary, mean +- standard error, "
      "the prediction (Markdown, LaTeX or CSV)");
  table_->add_option("results", table_results_, "results.csv of a campaign")->required();
  table_->add_option("--format", table_format_, "markdown, latex (booktabs) or csv")
      ->capture_default_str();
  table_->add_option("-o,--output", table_output_, "file to write (-: standard output)")
      ->capture_default_str()
      ->check(not_empty());
  table_
      ->add_option("--columns", table_columns_,
                   "results columns to show, in order (default: the settings that vary, "
                   "rmse_mean, predicted_rmse, rmse_ci_mean; mse_mean, predicted_mse under "
                   "velocity distributions)")
      ->delimiter(',');
  table_
      ->add_option("--digits", table_digits_,
                   "significant digits of each standard error (the mean to the same place)")
      ->check(CLI::Range(fss::kMinTableDigits, fss::kMaxTableDigits))
      ->capture_default_str();
}

void CampaignCommand::AddSpecOptions() {
  CLI::App& c = app();
  c.add_option("-f,--file", file_, "campaign file (JSON); options given override its fields");
  c.add_option("-i,--input", inputs_,
               "input PNG or TIFF images: files, directories (their *.png, *.tif, *.tiff), globs");
  c.add_option("-c,--code", codes_, "codes: built-in names or code files");
  c.add_option("-m,--mode", modes_, "modes: numerical, analog (default numerical)");
  c.add_option("-v,--velocity", velocity_,
               "velocities: V, a,b,c, start:stop:step or start:stop:xFACTOR")
      ->capture_default_str();
  // Distributions of velocities (docs/method.md §13): an axis in place of the velocities.
  c.add_option("--velocity-distribution", velocity_distributions_,
               "distributions of velocities, an axis in place of --velocity: uniform:LO:HI, "
               "normal:MEAN:SD, normal:MEAN:SD:LO:HI or files of 'velocity weight' lines");
  c.add_option("--restore-velocity", restore_velocity_,
               "velocities assumed by the restoration (default: the true one), as --velocity");
  c.add_option("--snr", snr_, "snr values, as --velocity")->capture_default_str();
  c.add_option("--dt", dt_, "time slot lengths, as --velocity")->capture_default_str();
  // The sensor (docs/method.md §10): the read noise is an axis, the rest fixed.
  c.add_option("--read-noise", read_noise_, "sensor read noises, electrons RMS, as --velocity")
      ->capture_default_str();
  c.add_option("--dark-current", dark_current_, "sensor dark current, electrons per slot")
      ->check(finite());
  c.add_option("--full-well", full_well_, "sensor full well, electrons (default none)")
      ->check(finite());
  c.add_option("--adc-bits", adc_bits_, "ADC bits, 1 to 32 (default 0: no ADC)");
  c.add_option("--adc-gain", adc_gain_, "ADC gain, electrons per count (needs --adc-bits)")
      ->check(finite());
  // The restorations (docs/method.md §12): an axis of restoration variants.
  c.add_option("--restoration", restorations_,
               "restorations: inverse, tikhonov, wiener, comma-separated, an axis (default "
               "inverse)")
      ->delimiter(',');
  c.add_option("--regularization", regularization_,
               "tikhonov's lambdas: values as --velocity, in [1e-8, 1e2], or optimal (default "
               "optimal)")
      ->delimiter(',');
  c.add_option("--prior", priors_,
               "wiener's priors: power-law, power-law:GAMMA, oracle, comma-separated (default "
               "power-law:2)")
      ->delimiter(',');
  c.add_option("--trials", trials_, "noise realizations per setting")
      ->check(at_least(1))
      ->capture_default_str();
  c.add_option("--seed", seed_, "campaign seed; each setting's seed derives from it")
      ->check(seed_value())
      ->capture_default_str();
  c.add_option("--noise", noise_, "noise model, any value of the simulation's --noise")
      ->capture_default_str();
  c.add_option("--rmse-margin", rmse_margin_,
               "RMSE margin in columns, -1 for the paper's 3B, or auto (the default): 3B where the "
               "image is wide enough (W >= 9B + 1), else the largest margin leaving a window of B "
               "columns")
      ->transform(rmse_margin_value(true));
  c.add_flag("--per-trial", per_trial_,
             "also write one row per trial (trials.csv, trials.jsonl): its seed, RMSE, RMSE_CI "
             "and PSNR (and its velocity, under a velocity distribution)");
  c.add_option("--threads", threads_,
               "threads (0: all); settings of small images run side by side, one thread each")
      ->check(at_least(0));
  c.add_option("-o,--output", output_, "campaign directory (created; rerun to resume)")
      ->check(not_empty());
  c.add_option("--shard", shard_, "run part I of N (I/N) into DIR; merge with 'campaign merge'")
      ->capture_default_str();
  c.add_flag("--figures", figures_, "also draw the figures into DIR/figures (PNG and SVG)");
  c.add_flag("--skip-unrunnable", skip_unrunnable_,
             "exit 0 even when some settings cannot run (they are listed on stderr and marked in "
             "results.csv)");
  c.add_flag("!--no-progress", progress_, "no progress line, even on a terminal");
}

int CampaignCommand::Run() const {
  return run_reporting_errors([this] {
    if (merge_->parsed() || check_->parsed() || table_->parsed()) {
      if (const std::string option = first_given_option(app()); !option.empty()) {
        fss::throw_usage_error(option + " is an option of 'campaign', not of 'campaign " +
                               (merge_->parsed()   ? "merge"
                                : check_->parsed() ? "check"
                                                   : "table") +
                               "'");
      }
    }
    if (merge_->parsed()) return Merge();
    if (check_->parsed()) return Check();
    if (table_->parsed()) return Table();
    return RunCampaign();
  });
}

fss::CampaignSpec CampaignCommand::Spec() const {
  fss::CampaignSpec spec;
  if (!file_.empty()) spec = fss::read_campaign_file(file_);
  // Without a file every option counts; with one, only those given.
  const auto use = [this](const char* name) { return file_.empty() || app().count(name) > 0; };
  if (use("--input")) spec.inputs = inputs_;
  if (use("--code")) spec.codes = codes_;
  if (use("--mode") && !modes_.empty()) spec.modes = parse_modes(modes_);
  // The velocity axis is velocities or distributions: either given here replaces the file's.
  const bool velocity_given = app().count("--velocity") > 0;
  const bool distribution_given = app().count("--velocity-distribution") > 0;
  if (velocity_given && distribution_given) {
    fss::throw_usage_error(
        "--velocity and --velocity-distribution: a setting has a velocity or a distribution of "
        "velocities, not both; give one");
  }
  if (use("--velocity")) spec.velocity = velocity_;
  if (velocity_given) spec.velocity_distributions.clear();
  if (distribution_given) {
    spec.velocity_distributions = velocity_distributions_;
    spec.velocity = "1";
  }
  if (use("--restore-velocity")) spec.restore_velocity = restore_velocity_;
  if (use("--snr")) spec.snr = snr_;
  if (use("--dt")) spec.dt = dt_;
  if (use("--trials")) spec.trials = trials_;
  if (use("--seed")) spec.seed = seed_;
  if (use("--noise")) spec.noise = parse_noise(noise_);
  if (use("--rmse-margin")) spec.rmse_margin_columns = rmse_margin_;
  if (use("--per-trial")) spec.per_trial = per_trial_;
  if (use("--read-noise")) spec.read_noise = read_noise_;
  if (use("--restoration")) spec.restorations = restorations_;
  if (use("--regularization")) spec.regularization = regularization_;
  if (use("--prior")) spec.priors = priors_;
  ApplySensorOptions(spec.sensor);
  return spec;
}

void CampaignCommand::ApplySensorOptions(fss::SensorModel& sensor) const {
  // Only the options given: the file's values, or the defaults, stay otherwise.
  const auto given = [this](const char* name) { return app().count(name) > 0; };
  if (given("--dark-current")) sensor.dark_current_electrons_per_slot = dark_current_;
  if (given("--full-well")) sensor.full_well_electrons = full_well_;
  if (given("--adc-bits")) sensor.adc_bits = adc_bits_;
  check_adc_gain(given("--adc-gain"), sensor.adc_bits);
  if (given("--adc-gain")) sensor.adc_gain_electrons_per_count = adc_gain_;
}

int CampaignCommand::RunCampaign() const {
  if (output_.empty()) fss::throw_usage_error("campaign needs -o DIR, its output directory");
  const fss::ResolvedCampaign campaign = fss::resolve_campaign(Spec());
  fss::CampaignRunOptions options;
  options.shard = fss::parse_shard(shard_);
  options.threads = threads_;
  options.fssim_version = FSS_VERSION;
  if (!file_.empty()) options.inputs.push_back(file_);
  if (figures_) refuse_inputs_among_figures(output_, campaign_inputs(file_, campaign));
  if (progress_ && isatty(STDERR_FILENO)) options.progress = print_progress;
  const fss::CampaignRunSummary summary = fss::RunCampaign(campaign, output_, options);
  std::printf("campaign %s: %lld settings (%lld run now, %lld from the journal) in %s\n",
              campaign.sha256.substr(0, 12).c_str(), summary.total, summary.ran, summary.resumed,
              output_.c_str());
  if (figures_) {
    if (options.shard.count > 1) {
      fss::write_stderr(
          "fssim: warning: --figures of a shard are left out; give --figures to "
          "'campaign merge'\n");
    } else {
      DrawFigures(campaign, summary.rows, output_);
    }
  }
  if (options.shard.count > 1) {
    // A shard records its gaps and exits 0 so that the merge runs; the merge reports them.
    return ReportGaps(campaign, summary.rows, "shard " + shard_, GapExit::kShard);
  }
  return ReportGaps(campaign, summary.rows, "campaign",
                    skip_unrunnable_ ? GapExit::kSkip : GapExit::kFail);
}

int CampaignCommand::Merge() const {
  if (merge_figures_) refuse_inputs_among_figures(merge_output_, parts_);
  fss::ResolvedCampaign campaign;
  const auto rows = fss::MergeCampaignParts(parts_, merge_output_, &campaign);
  std::printf("merged %zu parts: %zu settings of campaign %s into %s\n", parts_.size(), rows.size(),
              campaign.sha256.substr(0, 12).c_str(), merge_output_.c_str());
  if (merge_figures_) DrawFigures(campaign, rows, merge_output_);
  return ReportGaps(campaign, rows, "campaign merge",
                    merge_skip_unrunnable_ ? GapExit::kSkip : GapExit::kFail);
}

// Lists on stderr the settings that did not run; kExitRuntime when some cannot run and `exit`
// is kFail (settings that do not apply never fail).
int CampaignCommand::ReportGaps(const fss::ResolvedCampaign& campaign,
                                const std::vector<std::vector<std::string>>& rows,
                                const std::string& what, GapExit exit) const {
  const std::vector<fss::CampaignGap> gaps =
      fss::campaign_gaps(rows, campaign.has_velocity_distributions());
  std::string text;
  for (const std::string& line : fss::gap_report_lines(gaps, static_cast<long long>(rows.size()))) {
    text += "fssim: " + what + ": " + line + "\n";
  }
  const long long cannot_run = fss::count_gaps(gaps, fss::GapKind::kCannotRun);
  if (cannot_run > 0) {
    if (exit == GapExit::kShard) {
      text += "fssim: " + what +
              ": recorded; 'campaign merge' lists them again and fails unless given "
              "--skip-unrunnable\n";
    } else if (exit == GapExit::kFail) {
      text += "fssim: error: " + std::to_string(cannot_run) +
              " settings cannot run (the results of the others are written); change the "
              "settings listed or give --skip-unrunnable\n";
    }
  }
  if (!text.empty()) fss::write_stderr(text);
  return cannot_run > 0 && exit == GapExit::kFail ? kExitRuntime : kExitSuccess;
}

void CampaignCommand::DrawFigures(const fss::ResolvedCampaign& campaign,
                                  const std::vector<std::vector<std::string>>& rows,
                                  const std::string& dir) const {
  const std::vector<fss::CampaignFigure> figures = fss::campaign_figures(campaign, rows);
  const fs::path figure_dir = fs::path(dir) / "figures";
  // The inputs: the parts' journals of a merge, else the campaign's files.
  std::vector<std::string> inputs;
  if (merge_->parsed()) {
    for (const std::string& part : parts_) {
      inputs.push_back((fs::path(part) / fss::kCampaignJournal).string());
    }
  } else {
    inputs = campaign_inputs(file_, campaign);
  }
  for (const fss::CampaignFigure& f : figures) {
    for (const char* extension : {".png", ".svg"}) {
      refuse_output_over_inputs("the figure", (figure_dir / (f.name + extension)).string(), inputs);
    }
  }
  std::error_code ec;
  fs::create_directories(figure_dir, ec);
  if (ec) {
    fss::throw_runtime_error("cannot create " + shown_path(figure_dir.string()) + ": " +
                             ec.message());
  }
  for (const fss::CampaignFigure& f : figures) {
    fss::write_file_durably((figure_dir / (f.name + ".png")).string(),
                            std::string(f.png.begin(), f.png.end()));
    fss::write_file_durably((figure_dir / (f.name + ".svg")).string(), f.svg);
  }
  std::printf("%zu figure%s in %s\n", figures.size(), figures.size() == 1 ? "" : "s",
              figure_dir.c_str());
}

int CampaignCommand::Check() const {
  fss::CheckOptions options;
  options.columns = check_columns_;
  // Only the tolerances given: each replaces a default rule (docs/campaign.md).
  if (check_->count("--abs") > 0) options.abs_tolerance = abs_tolerance_;
  if (check_->count("--rel") > 0) options.rel_tolerance = rel_tolerance_;
  if (check_->count("--k-se") > 0) options.k_standard_errors = k_se_;
  options.exact = exact_;
  if (predicted_ && !expected_.empty()) {
    fss::throw_usage_error(
        "--predicted compares RESULTS.csv with its own predictions: give no "
        "EXPECTED.csv with it");
  }
  if (!predicted_ && expected_.empty()) {
    fss::throw_usage_error("campaign check needs EXPECTED.csv (or --predicted)");
  }
  std::vector<std::string> inputs = {results_};
  if (!expected_.empty()) inputs.push_back(expected_);
  if (!junit_.empty()) refuse_output_over_inputs("--junit", junit_, inputs);
  const fss::CheckReport report = predicted_
                                      ? fss::CheckCampaignPredictionFile(results_, options)
                                      : fss::CheckCampaignResultFiles(results_, expected_, options);
  for (const fss::CheckCase& c : report.cases) {
    if (!c.passed) std::printf("%s\n", c.message.c_str());
  }
  for (const std::string& line : report.summary) std::printf("%s\n", line.c_str());
  if (!junit_.empty()) {
    fss::write_file_in_folders(junit_, fss::check_junit_xml(report, "fssim campaign check"),
                               inputs);
  }
  std::printf("campaign check: %zu comparisons, %d deviations\n", report.cases.size(),
              report.failures());
  return report.failures() > 0 ? kExitRuntime : kExitSuccess;
}

int CampaignCommand::Table() const {
  fss::TableOptions options;
  const std::optional<fss::TableFormat> format = fss::table_format_from_string(table_format_);
  if (!format) {
    fss::throw_usage_error("--format " + shown_path(table_format_) +
                           ": expected markdown, latex or csv");
  }
  options.format = *format;
  options.columns = table_columns_;
  options.digits = table_digits_;
  if (!is_stdout(table_output_)) refuse_output_over_inputs("-o", table_output_, {table_results_});
  write_output(table_output_, fss::campaign_table_file(table_results_, options), {table_results_});
  return kExitSuccess;
}

}  // namespace fssim
