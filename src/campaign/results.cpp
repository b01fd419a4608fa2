#include "fss/campaign/results.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <utility>

#include "campaign/campaign_text.h"
#include "campaign/journal.h"
#include "fss/core/error.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/option_rules.h"

namespace fss {

namespace {

using campaign_text::shortest;

constexpr ColumnKind kText = ColumnKind::kText;
constexpr ColumnKind kNumber = ColumnKind::kNumber;
constexpr ColumnKind kBoolean = ColumnKind::kBoolean;

enum Column {
  kImage,
  kImageSha256,
  kCode,
  kCodeSha256,
  kCodeNormalizedL1,
  kMode,
  kVelocity,
  kRestoreVelocity,
  kSnr,
  kDt,
  kReadNoise,
  kDarkCurrent,
  kFullWell,
  kAdcBits,
  kAdcGain,
  kRestoration,
  kRegularization,
  kPrior,
  kNoise,
  kRmseMargin,
  kSeed,
  kTrials,
  kBlurLength,
  kRmseMean,
  kRmseSd,
  kRmseCiMean,
  kRmseCiSd,
  kPsnrMean,
  kSsimMean,
  kSsimSd,
  kPredictedRmse,
  kPredictedNoiseFree,
  kPredictedSigma,
  kSnrLevel100,
  kPredictedExact,
  kRegularizationApplied,
  kPriorLevel,
  kNoiseVariance,
  kInvertible,
  kStatus,
  kMessage,
  kFssimVersion,
  // Results schema 4: a campaign with velocity distributions (docs/method.md §13) has these
  // after the others; a campaign without has none of them.
  kVelocityDistribution,
  kMseMean,
  kMseSd,
  kPredictedMse,
  kColumnCount
};

// Every column, those of schema 4 included.
const std::vector<ResultColumn>& all_columns() {
  static const std::vector<ResultColumn> columns = {{"image", kText},
                                                    {"image_sha256", kText},
                                                    {"code", kText},
                                                    {"code_sha256", kText},
                                                    {"code_normalized_l1", kNumber},
                                                    {"mode", kText},
                                                    {"velocity", kNumber},
                                                    {"restore_velocity", kNumber},
                                                    {"snr", kNumber},
                                                    {"dt", kNumber},
                                                    {"read_noise", kNumber},
                                                    {"dark_current", kNumber},
                                                    {"full_well", kNumber},
                                                    {"adc_bits", kNumber},
                                                    {"adc_gain", kNumber},
                                                    {"restoration", kText},
                                                    {"regularization", kText},
                                                    {"prior", kText},
                                                    {"noise", kText},
                                                    {"rmse_margin", kNumber},
                                                    {"seed", kText},
                                                    {"trials", kNumber},
                                                    {"blur_length", kNumber},
                                                    {"rmse_mean", kNumber},
                                                    {"rmse_sd", kNumber},
                                                    {"rmse_ci_mean", kNumber},
                                                    {"rmse_ci_sd", kNumber},
                                                    {"psnr_mean", kNumber},
                                                    {"ssim_mean", kNumber},
                                                    {"ssim_sd", kNumber},
                                                    {"predicted_rmse", kNumber},
                                                    {"predicted_rmse_noise_free", kNumber},
                                                    {"predicted_sigma", kNumber},
                                                    {"snr_level100", kNumber},
                                                    {"predicted_exact", kBoolean},
                                                    {"regularization_applied", kNumber},
                                                    {"prior_level", kNumber},
                                                    {"noise_variance", kNumber},
                                                    {"invertible", kBoolean},
                                                    {"status", kText},
                                                    {"message", kText},
                                                    {"fssim_version", kText},
                                                    {"velocity_distribution", kText},
                                                    {"mse_mean", kNumber},
                                                    {"mse_sd", kNumber},
                                                    {"predicted_mse", kNumber}};
  return columns;
}

}  // namespace

const std::vector<ResultColumn>& campaign_columns() {
  static const std::vector<ResultColumn> columns(all_columns().begin(),
                                                 all_columns().begin() + kVelocityDistribution);
  return columns;
}

const std::vector<ResultColumn>& campaign_columns(bool with_distributions) {
  return with_distributions ? all_columns() : campaign_columns();
}

int campaign_column_index(std::string_view name) {
  const auto& columns = all_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (name == columns[i].name) return static_cast<int>(i);
  }
  return -1;
}

const std::vector<ResultColumn>& trial_columns() {
  static const std::vector<ResultColumn> columns = [] {
    // The setting columns: those before blur_length.
    std::vector<ResultColumn> c(campaign_columns().begin(),
                                campaign_columns().begin() + kBlurLength);
    c.insert(c.end(), {{"trial", kNumber},
                       {"trial_seed", kText},
                       {"rmse", kNumber},
                       {"rmse_ci", kNumber},
                       {"psnr", kNumber},
                       {"ssim", kNumber}});
    return c;
  }();
  return columns;
}

const std::vector<ResultColumn>& trial_columns(bool with_distributions) {
  static const std::vector<ResultColumn> wide = [] {
    std::vector<ResultColumn> c = trial_columns();
    c.insert(c.end(), {{"velocity_distribution", kText}, {"trial_velocity", kNumber}});
    return c;
  }();
  return with_distributions ? wide : trial_columns();
}

// Settings are image-, code-, mode- and velocity-major, so a kept plan serves every snr value,
// seed and image of one width of a code, mode, velocity, restore velocity and dt.
std::shared_ptr<const SimulationPlan> SimulationPlanCache::share(const SimulationOptions& options,
                                                                 int width,
                                                                 const ShutterCode& code) {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& kept : plans_) {
    if (kept->fits(options, width, code)) {
      ++reused_;
      return kept;
    }
  }
  plans_.push_back(std::make_shared<const SimulationPlan>(options, width, code));
  ++built_;
  bytes_ += plans_.back()->bytes();
  while (plans_.size() > 1 && (bytes_ > kMaxBytes || plans_.size() > kMaxPlans)) {
    bytes_ -= plans_.front()->bytes();
    plans_.pop_front();
  }
  return plans_.back();
}

const SimulationPlan& SimulationPlanCache::plan(const SimulationOptions& options, int width,
                                                const ShutterCode& code) {
  return *share(options, width, code);
}

long long SimulationPlanCache::built() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return built_;
}

long long SimulationPlanCache::reused() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return reused_;
}

namespace {

// A number that may be missing: empty then.
std::string optional_cell(const std::optional<double>& value) {
  return value ? shortest(*value) : std::string();
}

// The trial rows of a setting that ran: its setting cells, then each trial's; under a velocity
// distribution, then the distribution and the trial's velocity.
std::vector<ResultRow> trial_rows_of(const ResultRow& row, const SimulationReport& r) {
  std::vector<ResultRow> rows;
  const std::uint64_t seed = r.options.seed;
  const bool distribution = row.size() > static_cast<std::size_t>(kVelocityDistribution);
  for (std::size_t t = 0; t < r.trial_metrics.size(); ++t) {
    ResultRow trial(row.begin(), row.begin() + kBlurLength);
    const Metrics& m = r.trial_metrics[t];
    trial.insert(trial.end(), {std::to_string(t), std::to_string(seed + t), shortest(m.rmse),
                               shortest(m.rmse_ci), shortest(psnr(m.rmse)), optional_cell(m.ssim)});
    if (distribution) {
      trial.push_back(row[kVelocityDistribution]);
      trial.push_back(t < r.trial_velocities.size() ? shortest(r.trial_velocities[t]) : "");
    }
    rows.push_back(std::move(trial));
  }
  return rows;
}

// The cells every row has: the setting and its provenance.
ResultRow setting_cells(const ResolvedCampaign& c, const Setting& s, const SimulationOptions& o,
                        const SettingRunOptions& options) {
  ResultRow row(kColumnCount);
  row[kImage] = c.images[s.image].name;
  row[kImageSha256] = c.images[s.image].sha256;
  row[kCode] = c.codes[s.code].name;
  row[kCodeSha256] = c.codes[s.code].sha256;
  row[kCodeNormalizedL1] = shortest(normalized_l1(c.codes[s.code].code.gains));
  row[kMode] = to_string(o.mode);
  if (s.velocity_distribution >= 0) {
    // Under a distribution the velocity is each trial's: the velocity cell is empty, the
    // restore velocity's too unless given, and the distribution is named.
    if (o.restore_velocity_px_per_slot) {
      row[kRestoreVelocity] = shortest(*o.restore_velocity_px_per_slot);
    }
    row[kVelocityDistribution] = c.velocity_distributions[s.velocity_distribution].name;
  } else {
    row[kVelocity] = shortest(o.velocity_px_per_slot);
    row[kRestoreVelocity] =
        shortest(o.restore_velocity_px_per_slot.value_or(o.velocity_px_per_slot));
  }
  row[kSnr] = shortest(o.snr);
  row[kDt] = shortest(o.dt);
  // The sensor (docs/method.md §10): full_well empty for none, adc_gain
  // empty without an ADC.
  row[kReadNoise] = shortest(o.sensor.read_noise_electrons);
  row[kDarkCurrent] = shortest(o.sensor.dark_current_electrons_per_slot);
  if (o.sensor.full_well_electrons) row[kFullWell] = shortest(*o.sensor.full_well_electrons);
  row[kAdcBits] = std::to_string(o.sensor.adc_bits);
  if (o.sensor.adc_bits != 0) row[kAdcGain] = shortest(o.sensor.adc_gain_electrons_per_count);
  // The restoration (docs/method.md §12): Tikhonov's lambda as asked ("optimal" or a number),
  // Wiener's prior as parse_prior reads it.
  const RestorationOptions& r = o.restoration;
  row[kRestoration] = to_string(r.method);
  if (r.method == RestorationMethod::kTikhonov) {
    row[kRegularization] = r.regularization ? shortest(*r.regularization) : "optimal";
  }
  if (r.method == RestorationMethod::kWiener) row[kPrior] = prior_text(r);
  row[kNoise] = to_string(o.noise);
  // The margin as given (-1: the paper's 3B); under auto, the margin used once the setting ran
  // (run_setting), empty before.
  if (o.rmse_margin_columns != kRmseMarginAuto) {
    row[kRmseMargin] = std::to_string(o.rmse_margin_columns);
  }
  row[kSeed] = std::to_string(o.seed);
  row[kTrials] = std::to_string(o.trials);
  row[kFssimVersion] = options.fssim_version;
  return row;
}

}  // namespace

std::string row_setting_mismatch(const ResolvedCampaign& c, long long index, const ResultRow& row) {
  const Setting s = setting_at(c, index);
  const ResultRow expected = setting_cells(c, s, setting_options(c, s), SettingRunOptions{});
  const std::vector<ResultColumn>& columns = all_columns();
  for (int i = 0; i < kBlurLength; ++i) {
    // Under auto the margin is the one used: known once the setting ran.
    if (i == kRmseMargin && c.rmse_margin_columns == kRmseMarginAuto) continue;
    const auto at = static_cast<std::size_t>(i);
    if (row.size() <= at || row[at] != expected[at]) return columns[at].name;
  }
  const bool distributions = c.has_velocity_distributions();
  if (row.size() != campaign_columns(distributions).size() ||
      (distributions && row[kVelocityDistribution] != expected[kVelocityDistribution])) {
    return "velocity_distribution";
  }
  return {};
}

namespace {

// The columns results schema 3 added (the trial rows' ssim too): schema 2's are the others, in
// the same order.
constexpr std::string_view kAddedInSchema3[] = {
    "restoration", "regularization", "prior", "ssim_mean", "ssim_sd", "regularization_applied",
    "prior_level", "noise_variance", "ssim"};

// The names of `columns` that schema 2 had.
std::vector<std::string_view> schema2_names(const std::vector<ResultColumn>& columns) {
  std::vector<std::string_view> names;
  for (const ResultColumn& column : columns) {
    if (std::find(std::begin(kAddedInSchema3), std::end(kAddedInSchema3), column.name) ==
        std::end(kAddedInSchema3)) {
      names.emplace_back(column.name);
    }
  }
  return names;
}

// `old`, whose cells are those of `old_names`, in `columns`: the restoration of a schema 2 row is
// the inverse filter, and the cells it has no column for are empty.
ResultRow upgraded(const ResultRow& old, const std::vector<std::string_view>& old_names,
                   const std::vector<ResultColumn>& columns) {
  ResultRow row;
  row.reserve(columns.size());
  for (const ResultColumn& column : columns) {
    const auto at = std::find(old_names.begin(), old_names.end(), column.name);
    if (at != old_names.end()) {
      row.push_back(old[static_cast<std::size_t>(at - old_names.begin())]);
    } else {
      row.emplace_back(std::string_view(column.name) == "restoration" ? "inverse" : "");
    }
  }
  return row;
}

}  // namespace

std::optional<ResultRow> upgrade_schema2_row(const ResultRow& row, bool trial) {
  static const std::vector<std::string_view> kRowNames = schema2_names(campaign_columns());
  static const std::vector<std::string_view> kTrialNames = schema2_names(trial_columns());
  const std::vector<ResultColumn>& columns = trial ? trial_columns() : campaign_columns();
  const std::vector<std::string_view>& names = trial ? kTrialNames : kRowNames;
  if (row.size() != names.size()) return std::nullopt;
  return upgraded(row, names, columns);
}

namespace {

// `message` of SimulationOptions::IsValid with its fields named as the
// campaign's options and keys that set them.
std::string campaign_field_names(std::string message) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"sensor.read_noise_electrons", "--read-noise / \"read_noise\""},
      {"sensor.dark_current_electrons_per_slot", "--dark-current / \"dark_current\""},
      {"sensor.full_well_electrons", "--full-well / \"full_well\""},
      {"sensor.adc_gain_electrons_per_count", "--adc-gain / \"adc_gain\""},
      {"sensor.adc_bits", "--adc-bits / \"adc_bits\""},
      {"restore_velocity_px_per_slot", "--restore-velocity / \"restore_velocity\""},
      {"velocity_px_per_slot", "--velocity / \"velocity\""},
      {"rmse_margin_columns", "--rmse-margin / \"rmse_margin\""},
      {"velocity_distribution", "--velocity-distribution / \"velocity_distribution\""}};
  for (const auto& [field, shown] : kNames) {
    const std::size_t at = message.find(field);
    if (at != std::string::npos) message.replace(at, std::strlen(field), shown);
  }
  return message;
}

// The status and message of a setting that cannot run, "" when it can;
// *blur_length gets B when known.
std::pair<std::string, std::string> refusal(const ResolvedCampaign& c, const Setting& s,
                                            const SimulationOptions& o, const Image& image,
                                            int* blur_length) {
  std::string message;
  if (!o.IsValid(&message)) return {kStatusInvalid, campaign_field_names(message)};
  try {
    check_code_for_mode(c.codes[s.code].code, o.mode);
  } catch (const Error& e) {
    return {kStatusCodeRefused, e.what()};
  }
  // Under a distribution the geometry is that of the support's largest |v| (docs/method.md §13).
  const double true_v = o.velocity_distribution ? o.velocity_distribution->max_abs_velocity()
                                                : std::abs(o.velocity_px_per_slot);
  const double v = std::max(true_v, std::abs(o.restore_velocity_px_per_slot.value_or(0.0)));
  message = too_narrow_reason(image.width, c.codes[s.code].code.length(), v, o.dt,
                              o.rmse_margin_columns, blur_length);
  if (!message.empty()) return {kStatusTooNarrow, message};
  return {};
}

// Whether the kernel the run inverts is invertible. Under a velocity distribution, at every
// velocity the trials may draw: at the support's largest |v| (docs/method.md §13: the bands of
// smaller |v| are inside its band), at each velocity of a discrete one; or at the restore
// velocity when given. Otherwise the run's kernel.
bool run_invertible(const SimulationReport& r) {
  const SimulationOptions& o = r.options;
  if (!o.velocity_distribution) return r.kernel.invertible;
  const auto invertible_at = [&](double v) { return analyze_kernel(r.gains, v, o.dt).invertible; };
  if (o.restore_velocity_px_per_slot) return invertible_at(*o.restore_velocity_px_per_slot);
  const VelocityDistribution& d = *o.velocity_distribution;
  if (d.kind == VelocityDistributionKind::kDiscrete) {
    return std::all_of(d.points.begin(), d.points.end(),
                       [&](const VelocityPoint& p) { return invertible_at(p.velocity); });
  }
  return invertible_at(std::abs(d.low) > std::abs(d.high) ? d.low : d.high);
}

// The result cells of a setting that ran; its status.
const char* result_cells(const SimulationReport& r, ResultRow& row) {
  const Prediction& p = r.prediction;
  const bool inverse = r.options.restoration.method == RestorationMethod::kInverse;
  row[kBlurLength] = std::to_string(r.geometry.blur_length);
  row[kRmseMean] = shortest(r.trials.rmse_mean);
  row[kRmseSd] = shortest(r.trials.rmse_sd);
  row[kRmseCiMean] = shortest(r.trials.rmse_ci_mean);
  row[kRmseCiSd] = shortest(r.trials.rmse_ci_sd);
  row[kPsnrMean] = shortest(psnr(r.trials.rmse_mean));  // PSNR of the mean RMSE
  row[kSsimMean] = optional_cell(r.trials.ssim_mean);
  row[kSsimSd] = optional_cell(r.trials.ssim_sd);
  row[kPredictedRmse] = shortest(p.rmse);
  row[kPredictedNoiseFree] = shortest(p.rmse_noise_free);
  row[kPredictedSigma] = shortest(p.sigma);
  // The figure of merit of the inverse filter (docs/method.md §6): none for the others.
  if (inverse) row[kSnrLevel100] = shortest(p.snr_level100);
  row[kPredictedExact] = p.exact ? "true" : "false";
  row[kRegularizationApplied] = optional_cell(r.restoration.regularization);
  row[kPriorLevel] = optional_cell(r.restoration.prior_level);
  row[kNoiseVariance] = optional_cell(r.restoration.noise_variance);
  const bool invertible = run_invertible(r);
  row[kInvertible] = invertible ? "true" : "false";
  if (row.size() > static_cast<std::size_t>(kVelocityDistribution)) {
    // Under a distribution: the trials' mean and sd of MSE and E[MSE] (docs/method.md §13).
    row[kMseMean] = optional_cell(r.trials.mse_mean);
    row[kMseSd] = optional_cell(r.trials.mse_sd);
    row[kPredictedMse] = optional_cell(p.mse);
  }
  // Tikhonov and Wiener restore a code that is not invertible (they damp where K vanishes).
  return invertible || !inverse ? kStatusOk : kStatusNotInvertible;
}

}  // namespace

ResultRow run_setting(const ResolvedCampaign& c, const Setting& s, const Image& image,
                      const SettingRunOptions& options, SimulationPlanCache* plans,
                      std::vector<ResultRow>* trial_rows) {
  SimulationOptions o = setting_options(c, s);
  o.threads = options.threads;
  o.max_memory_bytes = options.max_memory_bytes;
  if (options.seed) o.seed = *options.seed;  // fssim sweep: one seed keeps its curves smooth
  if (trial_rows != nullptr) trial_rows->clear();
  ResultRow row = setting_cells(c, s, o, options);
  row.resize(campaign_columns(c.has_velocity_distributions()).size());
  int blur_length = -1;
  auto [status, message] = refusal(c, s, o, image, &blur_length);
  if (blur_length > 0) row[kBlurLength] = std::to_string(blur_length);
  if (status.empty()) {
    try {
      const ShutterCode& code = c.codes[s.code].code;
      const SimulationReport r = plans != nullptr
                                     ? Simulate(*plans->share(o, image.width, code), o, image, code)
                                     : Simulate(o, image, code);
      if (o.rmse_margin_columns == kRmseMarginAuto) row[kRmseMargin] = std::to_string(r.rmse_first);
      status = result_cells(r, row);
      if (trial_rows != nullptr) *trial_rows = trial_rows_of(row, r);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::kUsage) throw;
      status = kStatusFailed;
      message = e.what();
    }
  }
  row[kStatus] = status;
  row[kMessage] = escape_control_characters(message);
  return row;
}

namespace {

std::string table_csv(const std::vector<ResultColumn>& columns,
                      const std::vector<ResultRow>& rows) {
  std::string out;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) out += ',';
    out += columns[i].name;
  }
  out += "\n";
  for (const ResultRow& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) out += ",";
      out += campaign_text::csv_field(row[i]);
    }
    out += "\n";
  }
  return out;
}

std::string json_cell(const std::string& cell, ColumnKind kind) {
  if (kind == ColumnKind::kText) return campaign_text::json_quote(cell);
  if (cell.empty() || cell == "inf" || cell == "-inf" || cell == "nan") return "null";
  return cell;  // a number in shortest form, or true / false
}

std::string table_jsonl(const std::vector<ResultColumn>& columns,
                        const std::vector<ResultRow>& rows) {
  std::string out;
  for (const ResultRow& row : rows) {
    out += "{";
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) out += ",";
      out += campaign_text::json_quote(columns[i].name) + ":" + json_cell(row[i], columns[i].kind);
    }
    out += "}\n";
  }
  return out;
}

}  // namespace

std::string results_csv(const std::vector<ResultRow>& rows, bool with_distributions) {
  return table_csv(campaign_columns(with_distributions), rows);
}

std::string results_jsonl(const std::vector<ResultRow>& rows, bool with_distributions) {
  return table_jsonl(campaign_columns(with_distributions), rows);
}

std::string trials_csv(const std::vector<ResultRow>& rows, bool with_distributions) {
  return table_csv(trial_columns(with_distributions), rows);
}

std::string trials_jsonl(const std::vector<ResultRow>& rows, bool with_distributions) {
  return table_jsonl(trial_columns(with_distributions), rows);
}

}  // namespace fss
