// Regression checks of campaign results against expectations (the
// reference program's figures, or an earlier campaign): rows are matched by
// their settings, each quantity compared with its tolerance.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace fss {

// The default rules of the check (docs/campaign.md, "Regression checks"): numbers compare within
// this relative tolerance (floating-point round-off differs between processors) unless --rel or
// --exact is given; ...
inline constexpr double kExactRelativeTolerance = 1e-9;
// ... and a statistic (a mean over trials) within k standard errors, k chosen so that a whole
// check raises a false alarm with at most this probability (Student-t, Bonferroni) ...
inline constexpr double kCheckFalseAlarmRate = 1e-3;
// ... which needs its sd, so at least this many trials in each file.
inline constexpr int kMinStandardErrorTrials = 2;

struct CheckOptions {
  // Quantities to compare; empty: those EXPECTED has, by their role (src/campaign/column_roles):
  // the statistics (rmse_mean, rmse_ci_mean, ssim_mean, mse_mean) and the exact outputs
  // (predicted_*, blur_length, status, ...), not the derived psnr_mean, the *_sd, trials, seed,
  // digest, message and version columns.
  std::vector<std::string> columns;
  // The tolerances given (--abs, --rel, --k-se); a value passes within ANY of them. --rel
  // replaces the default kExactRelativeTolerance; --k-se applies to the statistics, whose
  // default k applies when none of the three is given.
  std::optional<double> abs_tolerance;
  std::optional<double> rel_tolerance;  // times |expected|
  // k sqrt(sd_r^2 / n_r + sd_e^2 / n_e), for a statistic of which both files carry the sd and
  // the trials.
  std::optional<double> k_standard_errors;
  // --exact: numbers equal, without the default relative tolerance (not with --abs or --rel).
  bool exact = false;

  bool IsValid(std::string* error) const;
};

// One comparison: a (setting, quantity), or a missing row (empty column).
struct CheckCase {
  std::string setting;  // "image=camera.png code=raskar snr=100 ..."
  std::string column;
  bool passed = false;
  std::string message;  // for a failure: the values, the difference, the tolerance
};

struct CheckReport {
  std::vector<CheckCase> cases;
  // What the check compared, with which tolerance, and what it left out: one line each
  // ("compared rmse_mean, ssim_mean: within k = 5.5 standard errors ...").
  std::vector<std::string> summary;
  int failures() const;
};

// Compares the rows of EXPECTED (CSV text; columns named as results.csv's,
// any subset) with RESULTS. Setting columns present in EXPECTED (image, code,
// mode, velocity, restore_velocity, snr, dt, noise, rmse_margin, the sensor's,
// restoration, regularization, prior, velocity_distribution) select the
// result row: numbers compare as numbers, and an image given as a bare file
// name matches a result image of that file name. Each quantity is compared by
// its role and the options (docs/campaign.md); report.summary says how.
// `*_name` arguments name the files in messages. Throws a usage fss::Error for
// malformed CSV, a column RESULTS lacks, an EXPECTED without any setting
// column, or a k-SE rule (given or default) that a file cannot serve: no sd or
// trials column, or a row with fewer than kMinStandardErrorTrials trials.
CheckReport CheckCampaignResults(const std::string& results_csv, const std::string& results_name,
                                 const std::string& expected_csv, const std::string& expected_name,
                                 const CheckOptions& options);

// Compares each measured mean of RESULTS (CSV text) with the row's own prediction: under a
// velocity distribution mse_mean with predicted_mse (the exact E[MSE] over the distribution,
// docs/method.md §13), otherwise rmse_mean with predicted_rmse; the standard error is the row's
// sd / sqrt(trials), so z = (mse_mean - predicted_mse) / (mse_sd / sqrt(trials)). Rows that did
// not run ok, have fewer than 2 trials or an infinite prediction are not compared. A value passes
// within any of the options' tolerances (--k-se K: |z| <= K; without tolerances the default k,
// trials - 1 degrees of freedom, over the rows compared). Throws a usage fss::Error for
// options.columns or options.exact (EXPECTED.csv's choices), malformed CSV, a column RESULTS
// lacks, or no row to compare.
CheckReport CheckCampaignPredictions(const std::string& results_csv,
                                     const std::string& results_name, const CheckOptions& options);

// Largest results or expectations file 'campaign check' reads (checked
// before reading; a stream is cut there): the results.csv of some million
// settings.
inline constexpr std::size_t kMaxCheckFileBytes = std::size_t{1} << 30;

// CheckCampaignResults on the files at `results_path` and `expected_path`,
// each read bounded by kMaxCheckFileBytes (a runtime fss::Error naming the
// file when larger or unreadable).
CheckReport CheckCampaignResultFiles(const std::string& results_path,
                                     const std::string& expected_path, const CheckOptions& options);

// CheckCampaignPredictions on the file at `results_path` (read as CheckCampaignResultFiles
// reads it).
CheckReport CheckCampaignPredictionFile(const std::string& results_path,
                                        const CheckOptions& options);

// The report as JUnit XML: one test case per comparison.
std::string check_junit_xml(const CheckReport& report, const std::string& suite_name);

// Parses CSV text (RFC 4180) into rows of fields; throws a usage fss::Error
// naming `name` for an unterminated quote or a row of the wrong width.
std::vector<std::vector<std::string>> parse_csv(const std::string& text, const std::string& name);

}  // namespace fss
