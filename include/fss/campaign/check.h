// Regression checks of campaign results against expectations (the
// reference program's figures, or an earlier campaign): rows are matched by
// their settings, each quantity compared with its tolerance.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace fss {

struct CheckOptions {
  // Quantities to compare; empty: every result quantity EXPECTED has
  // (rmse_mean, rmse_ci_mean, psnr_mean, ssim_mean, mse_mean, predicted_*, snr_level100,
  // regularization_applied, prior_level, noise_variance, status, invertible;
  // the *_sd, seed and trials columns serve the k-SE rule only).
  std::vector<std::string> columns;
  // A value passes when |result - expected| is within ANY of these; each
  // 0 disables its rule (all three 0: exact equality).
  double abs_tolerance = 0.0;
  double rel_tolerance = 0.0;  // times |expected|
  // k standard errors, for a *_mean column when both sides carry its _sd and
  // trials: k sqrt(sd_r^2 / n_r + sd_e^2 / n_e).
  double k_standard_errors = 0.0;

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
  int failures() const;
};

// Compares the rows of EXPECTED (CSV text; columns named as results.csv's,
// any subset) with RESULTS. Setting columns present in EXPECTED (image, code,
// mode, velocity, restore_velocity, snr, dt, noise, rmse_margin, the sensor's,
// restoration, regularization, prior, velocity_distribution) select the
// result row: numbers compare as numbers, and an image given as a bare file
// name matches a result image of that file name. `*_name` arguments name the
// files in messages. Throws a usage fss::Error for malformed CSV, a column
// RESULTS lacks, or an EXPECTED without any setting column.
CheckReport CheckCampaignResults(const std::string& results_csv, const std::string& results_name,
                                 const std::string& expected_csv, const std::string& expected_name,
                                 const CheckOptions& options);

// Compares each measured mean of RESULTS (CSV text) with the row's own prediction: under a
// velocity distribution mse_mean with predicted_mse (the exact E[MSE] over the distribution,
// docs/method.md §13), otherwise rmse_mean with predicted_rmse; the standard error is the row's
// sd / sqrt(trials), so z = (mse_mean - predicted_mse) / (mse_sd / sqrt(trials)). Rows that did
// not run ok, have fewer than 2 trials or an infinite prediction are not compared. A value passes
// within any of the options' tolerances (--k-se K: |z| <= K). Throws a usage fss::Error for
// options.columns (EXPECTED.csv's choice), malformed CSV, a column RESULTS lacks, or no row to
// compare.
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
