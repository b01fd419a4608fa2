#include "sweep_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <utility>

#include "campaign/campaign_text.h"
#include "cli_common.h"
#include "fss/campaign/results.h"
#include "fss/campaign/spec.h"
#include "fss/core/error.h"
#include "fss/io/image_io.h"
#include "fss/io/plot.h"
#include "fss/model/code.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/simulate.h"
#include "io/safe_write.h"
#include "range.h"

namespace fssim {

namespace {

const char kCsvHeader[] =
    "velocity,snr,blur_length,rmse_mean,rmse_sd,predicted_rmse,noise_free_rmse,snr_level100,"
    "invertible,status\n";
// With a restoration other than the inverse filter, the header and each row end with these
// columns (campaign results' columns of the same names); the inverse filter's CSV keeps its bytes.
const char kRestorationColumns[] =
    ",restoration,regularization,prior,regularization_applied,prior_level,noise_variance,"
    "ssim_mean,ssim_sd";

// Under a velocity distribution (docs/method.md §13), the header and each row end with these
// columns (campaign results' columns of the same names), and the velocity cells are empty.
const char kDistributionColumns[] = ",velocity_distribution,mse_mean,mse_sd,predicted_mse";

// CSV numbers: 10 significant digits for the swept values (so that 0.1 steps
// read 0.3, not 0.30000000000000004), full precision for the results.
constexpr int kSettingDigits = 10;
constexpr int kResultDigits = 17;

std::string csv_number(double value, int digits = kResultDigits) {
  return format_number(value, digits);
}

using Curves = SweepCommand::Curves;

// Turns the campaign engine's rows into the sweep's CSV rows and console
// lines; the curves get each row's point.
class SweepRows {
 public:
  SweepRows(bool by_velocity, bool restoration_columns, bool distribution, std::FILE* console)
      : by_velocity_(by_velocity),
        restoration_columns_(restoration_columns),
        distribution_(distribution),
        console_(console) {}

  // The CSV line of the setting (velocity, snr) from its campaign row.
  std::string Row(double velocity, double snr, const fss::ResultRow& row);
  const Curves& curves() const { return curves_; }

 private:
  std::string TooNarrowRow(double velocity, double snr, const fss::ResultRow& row);
  // The console line of a setting that ran, and its curves' point: the mean RMSE against the
  // predicted RMSE; under a distribution, sqrt of the trials' mean MSE against sqrt E[MSE].
  void VelocityLine(double velocity, double snr, const fss::ResultRow& row, bool invertible);
  void DistributionLine(double snr, const fss::ResultRow& row, bool invertible);
  // The curves' point at x: `y` with a bar of 1.96 standard errors `se` of the row's trials
  // (none with one trial), the prediction, and whether the RMSE margin is below 3B.
  void AddPoint(double x, const fss::ResultRow& row, double y, double se, double predicted);
  // The line's end: the restoration's cells (with restoration_columns_), the distribution's
  // (with distribution_) and the newline.
  std::string LineEnd(const fss::ResultRow& row) const;

  bool by_velocity_;
  bool restoration_columns_;
  bool distribution_;
  std::FILE* console_;  // stdout, or stderr when the CSV goes to stdout
  Curves curves_;
};

const std::string& cell(const fss::ResultRow& row, const char* column) {
  return row[static_cast<std::size_t>(fss::campaign_column_index(column))];
}

// A number cell of the row (shortest round-trip text: the same double).
double number(const fss::ResultRow& row, const char* column) {
  return std::strtod(cell(row, column).c_str(), nullptr);
}

// A number cell in the CSV's form, empty where the row has none.
std::string number_cell(const fss::ResultRow& row, const char* column) {
  return cell(row, column).empty() ? std::string() : csv_number(number(row, column));
}

std::string SweepRows::LineEnd(const fss::ResultRow& row) const {
  std::string end;
  if (restoration_columns_) {
    for (const char* text : {"restoration", "regularization", "prior"}) {
      end += "," + cell(row, text);
    }
    for (const char* column :
         {"regularization_applied", "prior_level", "noise_variance", "ssim_mean", "ssim_sd"}) {
      end += "," + number_cell(row, column);
    }
  }
  if (distribution_) {
    end += "," + fss::campaign_text::csv_field(cell(row, "velocity_distribution"));
    for (const char* column : {"mse_mean", "mse_sd", "predicted_mse"}) {
      end += "," + number_cell(row, column);
    }
  }
  return end + "\n";
}

// The rmse_margin cell holds the margin used, in columns (-1: 3B).
void SweepRows::AddPoint(double x, const fss::ResultRow& row, double y, double se,
                         double predicted) {
  const int trials = std::stoi(cell(row, "trials"));
  const double margin = number(row, "rmse_margin");
  curves_.x.push_back(x);
  curves_.measured.push_back(y);
  curves_.error.push_back(trials > 1 ? 1.96 * se : std::nan(""));
  curves_.predicted.push_back(std::isfinite(predicted) ? predicted : std::nan(""));
  curves_.open.push_back(margin >= 0.0 && margin < 3.0 * number(row, "blur_length"));
}

void SweepRows::VelocityLine(double velocity, double snr, const fss::ResultRow& row,
                             bool invertible) {
  const double mean = number(row, "rmse_mean"), sd = number(row, "rmse_sd");
  const double predicted = number(row, "predicted_rmse");
  const int trials = std::stoi(cell(row, "trials"));
  // The standard error of the mean RMSE: sd / sqrt(trials).
  AddPoint(by_velocity_ ? velocity : snr, row, mean, sd / std::sqrt(trials),
           invertible ? predicted : std::nan(""));
  if (invertible) {
    // A sensor that clips readouts makes the prediction approximate (method.md §10).
    const bool exact = cell(row, "predicted_exact") != "false";
    std::fprintf(console_, "velocity %g, snr %g: RMSE %f (sd %f, %d trial%s), predicted %f%s\n",
                 velocity, snr, mean, sd, trials, trials == 1 ? "" : "s", predicted,
                 exact ? "" : " (approximate: the sensor clips readouts)");
  } else {
    std::fprintf(console_, "velocity %g, snr %g: RMSE %g (%d trial%s), not invertible\n", velocity,
                 snr, mean, trials, trials == 1 ? "" : "s");
  }
}

void SweepRows::DistributionLine(double snr, const fss::ResultRow& row, bool invertible) {
  const double mse = number(row, "mse_mean");
  const double predicted = number(row, "predicted_mse");
  const int trials = std::stoi(cell(row, "trials"));
  // sqrt(mean MSE) against sqrt(E[MSE]) (docs/method.md §13); the standard error of
  // sqrt(mean MSE) to first order (delta method): that of the mean MSE over 2 sqrt(mean MSE).
  AddPoint(snr, row, std::sqrt(mse),
           number(row, "mse_sd") / std::sqrt(trials) / (2.0 * std::sqrt(mse)),
           std::sqrt(predicted));
  const std::string name = cell(row, "velocity_distribution");
  const std::string rmse = " (RMSE mean " + format_number(number(row, "rmse_mean")) + ", " +
                           std::to_string(trials) + (trials == 1 ? " trial)" : " trials)");
  if (std::isfinite(predicted)) {
    std::fprintf(
        console_, "velocity %s, snr %g: MSE mean %f%s, predicted expected MSE %f%s\n", name.c_str(),
        snr, mse, rmse.c_str(), predicted,
        cell(row, "predicted_exact") != "false" ? "" : " (approximate: the sensor clips readouts)");
  } else {
    std::fprintf(console_,
                 "velocity %s, snr %g: MSE mean %f%s, predicted expected MSE infinite%s\n",
                 name.c_str(), snr, mse, rmse.c_str(), invertible ? "" : " (not invertible)");
  }
}

std::string SweepRows::TooNarrowRow(double velocity, double snr, const fss::ResultRow& row) {
  const std::string distribution = distribution_ ? cell(row, "velocity_distribution") : "";
  fss::write_stderr("fssim: warning: velocity " +
                    (distribution_ ? distribution : format_exact(velocity)) + ": " +
                    cell(row, "message") + "; row marked too-narrow\n");
  curves_.x.push_back(by_velocity_ ? velocity : snr);
  curves_.too_narrow.push_back(format_number(by_velocity_ ? velocity : snr));
  curves_.measured.push_back(std::nan(""));
  curves_.error.push_back(std::nan(""));
  curves_.predicted.push_back(std::nan(""));
  curves_.open.push_back(false);
  if (distribution_) {
    std::fprintf(console_, "velocity %s, snr %g: too narrow\n", distribution.c_str(), snr);
  } else {
    std::fprintf(console_, "velocity %g, snr %g: too narrow\n", velocity, snr);
  }
  return cell(row, "blur_length") + ",,,,,,,too-narrow" + LineEnd(row);
}

std::string SweepRows::Row(double velocity, double snr, const fss::ResultRow& row) {
  const std::string setting = (distribution_ ? "" : csv_number(velocity, kSettingDigits)) + "," +
                              csv_number(snr, kSettingDigits) + ",";
  const std::string& status = cell(row, "status");
  if (status == fss::kStatusTooNarrow) return setting + TooNarrowRow(velocity, snr, row);
  if (status != fss::kStatusOk && status != fss::kStatusNotInvertible) {
    fss::throw_usage_error(cell(row, "message"));  // what Simulate refused
  }
  const bool invertible = status == fss::kStatusOk;
  const double mean = number(row, "rmse_mean"), sd = number(row, "rmse_sd");
  const double predicted = number(row, "predicted_rmse");
  if (distribution_) {
    DistributionLine(snr, row, invertible);
  } else {
    VelocityLine(velocity, snr, row, invertible);
  }
  return setting + cell(row, "blur_length") + "," + csv_number(mean) + "," + csv_number(sd) + "," +
         csv_number(predicted) + "," + csv_number(number(row, "predicted_rmse_noise_free")) + "," +
         number_cell(row, "snr_level100") + "," + cell(row, "invertible") + "," + status +
         LineEnd(row);
}

// Every value of --snr 'TEXT' as the simulator's rule has it (> 0, within
// the library's range). The message shows TEXT as typed, and for a range
// the value that breaks the rule.
void check_snr_values(const std::vector<double>& snrs, const std::string& text) {
  for (const double snr : snrs) {
    const std::string rule = snr > 0.0 ? fss::scale_rule(snr) : "must be > 0";
    if (rule.empty()) continue;
    std::string message = "--snr '" + text + "': ";
    message += snrs.size() == 1 ? "the value " + rule
                                : "every value " + rule + ", the range holds " + format_exact(snr);
    fss::throw_usage_error(message);
  }
}

}  // namespace

SweepCommand::SweepCommand(CLI::App& parent)
    : Command(
          parent, "sweep",
          "simulate over a range of velocities and/or snr values and write one CSV row per setting "
          "(measured and predicted RMSE)") {
  CLI::App& sweep = app();
  sweep.add_option("-i,--input", input_, "input PNG or TIFF image")->required();
  flags_.AddCode(sweep);
  flags_.AddMode(sweep);
  velocity_option_ =
      sweep
          .add_option("-v,--velocity", velocity_,
                      "velocity V, or a range start:stop:step (inclusive stop), pixels per slot")
          ->capture_default_str();
  flags_.AddVelocityDistribution(sweep);
  sweep.add_option("--snr", snr_, "snr S, or a range start:stop:step; values > 0")
      ->capture_default_str();
  flags_.AddDt(sweep);
  flags_.AddTrials(sweep);
  flags_.AddSeed(sweep);
  flags_.AddNoise(sweep);
  flags_.AddRmseMargin(sweep);
  flags_.AddThreads(sweep);
  flags_.AddMaxMemory(sweep);  // the simulator's memory guard, for the image and each row
  flags_.AddSensor(sweep);
  flags_.AddRestoration(sweep);
  sweep.add_option("-o,--output", output_, "CSV file to write (-: standard output)")->required();
  sweep.add_option("--plot", plot_,
                   "also draw the measured RMSE (bars of 1.96 standard errors) and the "
                   "predicted curve against the swept parameter into this PNG, with an SVG "
                   "beside it (FILE.svg: the SVG alone; one of --velocity, --snr must be a "
                   "range)");
}

int SweepCommand::Run() const {
  const ErrorContext context{" (raise it with --max-memory)", ""};
  return run_reporting_errors([this] { return Sweep(); }, &context);
}

SweepCommand::Grid SweepCommand::ParseGrid() const {
  Grid grid{parse_range(velocity_, "--velocity"), parse_range(snr_, "--snr")};
  check_snr_values(grid.snrs, snr_);
  const std::size_t settings = grid.velocities.size() * grid.snrs.size();
  if (settings > static_cast<std::size_t>(kMaxRangePoints)) {
    fss::throw_usage_error("--velocity '" + velocity_ + "' and --snr '" + snr_ + "' make " +
                           std::to_string(settings) + " settings, more than " +
                           std::to_string(kMaxRangePoints));
  }
  if (!plot_.empty() && grid.velocities.size() > 1 && grid.snrs.size() > 1) {
    fss::throw_usage_error(
        "--plot draws one curve: give a range to --velocity or to --snr, not "
        "to both");
  }
  return grid;
}

// The inputs (image, code file) are never written over (write_output
// checks them again), and --output and --plot must be two files.
void SweepCommand::CheckPaths() const {
  const std::vector<std::string> inputs = {input_, flags_.code_name()};
  for (const auto& [option, path] : {std::pair{"--output", &output_}, {"--plot", &plot_}}) {
    for (const std::string& input : inputs) {
      if (!path->empty() && !is_stdout(*path) && fss::same_file(*path, input)) {
        fss::throw_runtime_error(std::string(option) + " '" + *path + "' is the input '" + input +
                                 "': refusing to write over it");
      }
    }
  }
  if (!plot_.empty() && (is_stdout(plot_) ? is_stdout(output_) : fss::same_file(plot_, output_))) {
    fss::throw_usage_error("--plot '" + plot_ + "' and --output '" + output_ +
                           "' are the same file: give two");
  }
  // The SVG written beside the PNG.
  if (const std::string svg = PlotPaths().second; !svg.empty() && svg != plot_) {
    for (const std::string& input : inputs) {
      if (fss::same_file(svg, input)) {
        fss::throw_runtime_error("--plot '" + plot_ + "' writes its SVG to '" + svg +
                                 "', the input '" + input + "': refusing to write over it");
      }
    }
    if (!is_stdout(output_) && fss::same_file(svg, output_)) {
      fss::throw_usage_error("--plot '" + plot_ + "' writes its SVG to '" + svg +
                             "', the same file as --output: give another");
    }
  }
}

// The sweep as a campaign of one image and one code over the grid, every
// setting with the seeds --seed, --seed + 1, ... (SettingRunOptions::seed).
fss::ResolvedCampaign SweepCommand::Campaign(const Grid& grid, const fss::ShutterCode& code,
                                             const fss::SimulationOptions& options) const {
  fss::ResolvedCampaign c;
  c.images = {{input_, input_, ""}};
  c.codes = {{code.name, code, ""}};
  c.modes = {options.mode};
  c.velocities.values = grid.velocities;
  c.restore_velocities = {std::nullopt};
  c.snrs.values = grid.snrs;
  c.dts.values = {options.dt};
  c.trials = options.trials;
  c.seed = options.seed;
  c.noise = options.noise;
  c.rmse_margin_columns = options.rmse_margin_columns;
  // The sensor (--read-noise, --dark-current, ...): every setting's.
  c.read_noises.values = {options.sensor.read_noise_electrons};
  c.sensor = options.sensor;
  // The restoration (--restoration, --regularization, --prior): every setting's.
  c.restorations = {options.restoration};
  // The velocity distribution (docs/method.md §13): every setting's, in place of the velocity.
  if (options.velocity_distribution) {
    const fss::VelocityDistribution& d = *options.velocity_distribution;
    c.velocity_distributions = {
        {d.kind == fss::VelocityDistributionKind::kDiscrete ? d.source : d.text(), d, ""}};
  }
  return c;
}

// The figure of --plot: the measured RMSE with bars of 1.96 standard errors against the
// predicted curve over the swept parameter; under a velocity distribution, sqrt(mean MSE)
// against sqrt(E[MSE]) (docs/method.md §13). Open markers: RMSE margin below 3B.
SweepCommand::PlotPictures SweepCommand::Plot(const Grid& grid, const fss::ShutterCode& code,
                                              const fss::SimulationOptions& options,
                                              const Curves& c) const {
  const auto& distribution = options.velocity_distribution;
  const std::string velocity =
      distribution ? distribution->text() : format_number(grid.velocities.front());
  fss::PlotOptions plot_options;
  const std::string code_name = std::filesystem::path(code.name).filename().string();
  plot_options.title = (distribution ? "sqrt(mean MSE)" : "RMSE") + std::string(" of code ") +
                       code_name + " on " + std::filesystem::path(input_).filename().string() +
                       ", " + fss::to_string(options.mode) +
                       (grid.by_velocity() ? ", snr " + format_number(grid.snrs.front())
                                           : ", velocity " + velocity) +
                       (options.restoration.method != fss::RestorationMethod::kInverse
                            ? ", " + fss::describe(options.restoration)
                            : "");
  fss::MeasuredFigure figure;
  figure.x = c.x;
  figure.series = {{code_name, c.measured, c.error, c.predicted, c.open, 0}};
  figure.x_label = grid.by_velocity() ? "velocity (pixels per time slot)" : "snr";
  figure.log_x = !grid.by_velocity();
  figure.y_label = distribution ? "sqrt(mean MSE) (gray levels)" : "RMSE (gray levels)";
  const std::string trials =
      std::to_string(options.trials) + (options.trials == 1 ? " trial" : " trials");
  figure.points_key = std::string("measured: ") + (distribution ? "sqrt(mean MSE)" : "mean") +
                      " of " + trials + (options.trials > 1 ? " ± 1.96 SE" : "");
  figure.predicted_key = distribution ? "predicted: sqrt(E[MSE])" : "predicted";
  figure.open_key = "RMSE margin < 3B";
  if (!c.too_narrow.empty()) {
    std::string values;
    for (const std::string& value : c.too_narrow) values += (values.empty() ? "" : ", ") + value;
    figure.notes = {"no result: " + figure.x_label.substr(0, figure.x_label.find(' ')) + " " +
                    values + " (too-narrow)"};
  }
  return {fss::plot_measured_png(figure, plot_options),
          fss::plot_measured_svg(figure, plot_options)};
}

// --plot X.svg writes the SVG alone; --plot - the PNG alone (on standard output); any other
// --plot X the PNG and, beside it, the SVG (X with its extension replaced by .svg).
std::pair<std::string, std::string> SweepCommand::PlotPaths() const {
  if (plot_.empty() || is_stdout(plot_)) return {plot_, ""};
  std::filesystem::path svg(plot_);
  std::string extension = svg.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (extension == ".svg") return {"", plot_};
  return {plot_, svg.replace_extension(".svg").string()};
}

void SweepCommand::WritePlot(const PlotPictures& pictures, const std::vector<std::string>& inputs,
                             std::FILE* console) const {
  const auto [png, svg] = PlotPaths();
  if (!png.empty()) {
    write_output(
        png,
        std::string_view(reinterpret_cast<const char*>(pictures.png.data()), pictures.png.size()),
        inputs);
    std::fprintf(console, "Plot: %s\n", png.c_str());
  }
  if (!svg.empty()) {
    write_output(svg, pictures.svg, inputs);
    std::fprintf(console, "Plot: %s\n", svg.c_str());
  }
}

int SweepCommand::Sweep() const {
  const Grid grid = ParseGrid();
  CheckPaths();
  const fss::ShutterCode code = fss::load_code(flags_.code_name(), "--code");
  const fss::SimulationOptions options = flags_.Options();
  if (options.velocity_distribution && velocity_option_->count() > 0) {
    fss::throw_usage_error(
        "--velocity-distribution: cannot be used with -v/--velocity (each trial draws its "
        "velocity from the distribution; sweep --snr under it)");
  }
  const fss::Image image = fss::read_image(input_, options.max_memory_bytes);
  // Refuse a code the mode cannot use before any row runs (Simulate would, at
  // the first setting that fits the image).
  fss::check_code_for_mode(code, options.mode);
  const bool on_stdout = is_stdout(output_) || is_stdout(plot_);
  // The campaign engine runs the settings (velocity-major, as the CSV), each
  // kernel once per velocity.
  const fss::ResolvedCampaign campaign = Campaign(grid, code, options);
  const fss::SettingRunOptions run{options.threads, options.max_memory_bytes, "", options.seed};
  fss::SimulationPlanCache plans;
  const bool restoration_columns = options.restoration.method != fss::RestorationMethod::kInverse;
  const bool distribution = options.velocity_distribution.has_value();
  SweepRows rows(grid.by_velocity(), restoration_columns, distribution,
                 on_stdout ? stderr : stdout);
  std::string csv = kCsvHeader;
  if (restoration_columns) csv.insert(csv.size() - 1, kRestorationColumns);
  if (distribution) csv.insert(csv.size() - 1, kDistributionColumns);
  const long long settings = campaign.setting_count();
  for (long long i = 0; i < settings; ++i) {
    const fss::Setting s = fss::setting_at(campaign, i);
    csv += rows.Row(grid.velocities[s.velocity], grid.snrs[s.snr],
                    fss::run_setting(campaign, s, image, run, &plans));
  }
  const Curves& curves = rows.curves();
  const bool drawn = std::any_of(curves.measured.begin(), curves.measured.end(),
                                 [](double v) { return std::isfinite(v); });
  if (!plot_.empty() && !drawn) {
    fss::write_stderr("fssim: warning: --plot '" + plot_ +
                      "': no setting has a result to draw; no plot written\n");
  }
  const PlotPictures pictures =
      plot_.empty() || !drawn ? PlotPictures{} : Plot(grid, code, options, curves);
  std::vector<std::string> inputs = {input_, flags_.code_name()};
  if (const std::string file = flags_.velocity_distribution_file(options); !file.empty()) {
    inputs.push_back(file);
  }
  std::FILE* console = on_stdout ? stderr : stdout;
  write_output(output_, csv, inputs);
  std::fprintf(console, "Wrote %lld row%s to %s\n", settings, settings == 1 ? "" : "s",
               output_.c_str());
  if (!plot_.empty() && drawn) WritePlot(pictures, inputs, console);
  return kExitSuccess;
}

}  // namespace fssim
