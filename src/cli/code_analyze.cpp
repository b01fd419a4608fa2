// `fssim code analyze`.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.h"
#include "code_commands.h"
#include "fss/model/code.h"

namespace fssim {

namespace {

// The analysis grid in words, for the M line.
std::string grid_description(int grid) {
  if (grid == 0) {
    return std::to_string(2 * fss::kBandGridPoints) + "-node midpoint rule on [-pi, pi]";
  }
  return std::to_string(grid) + "-point DFT grid";
}

nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The sensor's part of the JSON, present only when a sensor option is on (a
// default run writes the photon-noise JSON unchanged).
void add_sensor_json(const fss::CodeAnalysis& a, nlohmann::json* j) {
  if (!a.sensor.enabled()) return;
  nlohmann::json sensor = {
      {"read_noise_electrons", a.sensor.read_noise_electrons},
      {"dark_current_electrons_per_slot", a.sensor.dark_current_electrons_per_slot},
      {"adc_bits", a.sensor.adc_bits}};
  if (a.sensor.adc_bits != 0) {
    sensor["adc_gain_electrons_per_count"] = a.sensor.adc_gain_electrons_per_count;
  }
  (*j)["parameters"]["sensor"] = sensor;
  (*j)["analysis"]["readouts"] = a.readouts;
  (*j)["analysis"]["readout_variance_electrons2"] = a.readout_variance_electrons2;
  (*j)["analysis"]["effective_q"] = a.effective_q;
  (*j)["analysis"]["effective_noise_figure"] = finite_or_null(a.effective_noise_figure);
}

// The restoration's part of the JSON, present only for a Wiener or Tikhonov
// restoration (the inverse filter's JSON is unchanged): the criterion, its
// prior (Tikhonov: the one that measures its bias) and lambda, and E.
void add_restoration_json(const fss::CodeAnalysis& a, nlohmann::json* j) {
  const fss::RestorationOptions& r = a.restoration;
  if (r.method == fss::RestorationMethod::kInverse) return;
  nlohmann::json restoration = {{"method", fss::to_string(r.method)},
                                {"prior", "power-law"},
                                {"gamma", r.prior_exponent},
                                {"C", r.prior_level.value_or(fss::kDefaultPriorLevel)}};
  if (r.method == fss::RestorationMethod::kTikhonov) {
    restoration["lambda"] =
        std::isfinite(a.restoration_error) ? nlohmann::json(a.regularization) : nlohmann::json();
    restoration["lambda_optimal"] = !r.regularization.has_value();
    (*j)["analysis"]["snapshot_regularization"] = a.snapshot_regularization;
  }
  (*j)["parameters"]["restoration"] = restoration;
  (*j)["analysis"]["restoration_error"] = a.restoration_error;
}

// The distribution's part of the JSON, present only under --velocity-distribution: the
// distribution in place of the velocity, the averaged error, the worst velocity and the
// quadrature.
void add_velocity_distribution_json(const fss::CodeAnalysis& a, nlohmann::json* j) {
  if (!a.velocity_distribution) return;
  const fss::VelocityDistribution& d = *a.velocity_distribution;
  nlohmann::json distribution = {
      {"spec", d.text()}, {"description", d.describe()}, {"low", d.low}, {"high", d.high}};
  if (d.kind == fss::VelocityDistributionKind::kNormal) {
    distribution["mean"] = d.mean;
    distribution["sd"] = d.sd;
  }
  if (d.kind == fss::VelocityDistributionKind::kDiscrete) {
    nlohmann::json points = nlohmann::json::array();
    for (const fss::VelocityPoint& p : d.points) points.push_back({p.velocity, p.weight});
    distribution["points"] = points;
  }
  (*j)["parameters"].erase("velocity");
  (*j)["parameters"]["velocity_distribution"] = distribution;
  nlohmann::json& analysis = (*j)["analysis"];
  analysis["kernel_velocity"] = a.velocity;
  analysis["restoration_error"] = finite_or_null(a.restoration_error);
  analysis["worst_velocity"] = a.worst_velocity;
  analysis["worst_snr_level100"] = a.worst_snr_level100;
  analysis["quadrature"] = {
      {"rule", d.kind == fss::VelocityDistributionKind::kDiscrete || d.is_point()
                   ? "exact sum"
                   : "adaptive gauss-kronrod 7/15"},
      {"relative_tolerance", fss::kVelocityQuadratureTolerance},
      {"evaluations", a.quadrature_evaluations},
      {"intervals", a.quadrature_intervals},
      {"error_estimate", a.quadrature_error_estimate},
      {"converged", a.quadrature_converged}};
}

nlohmann::json analysis_json(const fss::ShutterCode& code, const fss::CodeAnalysis& a) {
  nlohmann::json j;
  j["code"] = {{"name", code.name}, {"length", a.length}, {"gains", code.gains}};
  j["parameters"] = {{"mode", fss::to_string(a.mode)},
                     {"velocity", a.velocity},
                     {"dt", a.dt},
                     {"snr", a.snr},
                     {"grid", a.grid == 0 ? "midpoint" : "dft"},
                     {"grid_points", a.grid == 0 ? 2 * fss::kBandGridPoints : a.grid}};
  j["analysis"] = {{"sum", a.sum},
                   {"square_sum", a.square_sum},
                   {"normalized_l1", a.normalized_l1},
                   {"k0", a.k0},
                   {"min_abs", a.min_abs},
                   {"min_abs_xi", a.min_abs_xi},
                   {"invertible", a.invertible},
                   {"q", a.q},
                   {"m", finite_or_null(a.m)},
                   {"noise_figure", finite_or_null(a.noise_figure)},
                   {"snr_level100", a.snr_level100},
                   {"snapshot_snr_level100", a.snapshot_snr_level100},
                   {"ratio_to_snapshot", a.ratio_to_snapshot},
                   {"snr_level100_bound", finite_or_null(a.snr_level100_bound)}};
  add_sensor_json(a, &j);
  add_restoration_json(a, &j);
  add_velocity_distribution_json(a, &j);
  return j;
}

// A figure as "%f" writes it where that shows its digits (0, or
// 1e-3 <= |x| < 1e6: the paper's codes), else as "%.6g": 1e-48 is not
// "0.000000" and 3e100 not a hundred digits.
std::string decimal(double x) {
  const double a = std::abs(x);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, a == 0.0 || (a >= 1e-3 && a < 1e6) ? "%f" : "%.6g", x);
  return buffer;
}

// Under a velocity distribution: the distribution, how the error was averaged over it.
void print_velocity_average(const fss::CodeAnalysis& a) {
  std::printf("Velocity distribution: %s\n", a.velocity_distribution->describe().c_str());
  std::printf("Averaged over it (each velocity restored at itself): %s\n",
              fss::describe_velocity_average(a).c_str());
}

// Under a velocity distribution: the worst velocity of the support and its SNR, or where the
// code is not invertible.
void print_worst_velocity(const fss::CodeAnalysis& a) {
  if (a.worst_snr_level100 > 0.0) {
    std::printf("Worst velocity: %s (SNR at level 100 there: %s)\n",
                format_number(a.worst_velocity).c_str(), decimal(a.worst_snr_level100).c_str());
  } else {
    std::printf("Not invertible at velocity %s: the expected error is infinite\n",
                format_exact(a.worst_velocity).c_str());
  }
}

// The motion of the setting: the velocity, or the distribution.
std::string motion_description(const fss::CodeAnalysis& a) {
  if (!a.velocity_distribution) return "velocity " + format_exact(a.velocity);
  return "velocity distribution " + a.velocity_distribution->text();
}

// The kernel's lines: min |K| and invertibility (under a distribution, at the support's largest
// |v|, and over the whole support).
void print_kernel(const fss::CodeAnalysis& a, bool averaged) {
  const std::string where =
      averaged ? " (at velocity " + format_exact(a.velocity) + ", the support's largest |v|)" : "";
  std::printf("Min |K| on the band: %g at xi = %s%s\n", a.min_abs, decimal(a.min_abs_xi).c_str(),
              where.c_str());
  if (a.invertible) {
    std::printf("Invertible: yes%s\n", averaged ? " (at every velocity of the support)" : "");
  } else {
    std::printf("Invertible: no (K vanishes on the band%s)\n",
                averaged ? " within the support" : "");
  }
}

// The lines after the snapshot's: Tikhonov's lambda, and the bound.
void print_regularization_and_bound(const fss::CodeAnalysis& a, bool averaged) {
  const fss::RestorationMethod method = a.restoration.method;
  if (method == fss::RestorationMethod::kTikhonov) {
    // no lambda where E is infinite (a code of zero sum, level100_restoration_error)
    const std::string lambda =
        std::isfinite(a.restoration_error) ? format_number(a.regularization) : "none";
    std::printf("Regularization: lambda %s (snapshot %s)%s\n", lambda.c_str(),
                format_number(a.snapshot_regularization).c_str(),
                averaged && !a.restoration.regularization
                    ? " at the worst velocity; each velocity is restored with its own optimal "
                      "lambda"
                    : "");
  }
  if (method != fss::RestorationMethod::kInverse) {
    std::printf(
        "Bound on the SNR at level 100: none for the %s restoration (the Cauchy-Schwarz "
        "bound is the inverse filter's)\n",
        fss::to_string(method).c_str());
  } else if (std::isfinite(a.snr_level100_bound)) {
    std::printf("Bound on the SNR at level 100 (any code, any length%s): %s\n",
                averaged ? ", the bound of Q M averaged over the velocities" : "",
                decimal(a.snr_level100_bound).c_str());
  } else {
    std::printf("Bound on the SNR at level 100 (any code, any length): none at v = 0\n");
  }
}

void print_analysis(const fss::ShutterCode& code, const fss::CodeAnalysis& a,
                    const std::string& mode) {
  const bool averaged = a.velocity_distribution.has_value() && !a.velocity_distribution->is_point();
  std::printf("Code: %s (L = %d)\n", code.name.c_str(), a.length);
  std::printf("Setting: %s mode, %s, dt %s, snr %s\n", mode.c_str(), motion_description(a).c_str(),
              format_exact(a.dt).c_str(), format_exact(a.snr).c_str());
  if (a.sensor.enabled()) {
    std::printf("Sensor: %s (%s photo-electrons per gray level per slot)\n",
                fss::describe_design_sensor(a.sensor).c_str(),
                format_exact(a.snr * a.snr / 100.0).c_str());
  }
  std::printf("Sum of gains: %s\n", decimal(a.sum).c_str());
  std::printf("Sum of squares: %s\n", decimal(a.square_sum).c_str());
  std::printf("Normalized L1 norm: %s\n", decimal(a.normalized_l1).c_str());
  print_kernel(a, averaged);
  std::printf("Q: %s\n", decimal(a.q).c_str());
  if (a.sensor.enabled()) {
    std::printf("Readouts: %s, each adding %s e-^2\n", decimal(a.readouts).c_str(),
                format_exact(a.readout_variance_electrons2).c_str());
    std::printf("Effective Q (photon noise and readouts): %s\n", decimal(a.effective_q).c_str());
  }
  const std::string m_rule =
      grid_description(a.grid) + (averaged ? ", averaged over the velocities" : "");
  std::printf("M (mean of 1/|K|^2, %s): %s\n", m_rule.c_str(),
              std::isfinite(a.m) ? decimal(a.m).c_str() : "infinite");
  // Not a simulated image's predicted RMSE, which is the exact expectation (§6b).
  std::printf("Figure of merit (stationary approximation, image-independent):\n");
  if (a.restoration.method != fss::RestorationMethod::kInverse) {
    std::printf("Criterion: %s\n", fss::describe_design_criterion(a.restoration).c_str());
  }
  if (a.velocity_distribution) print_velocity_average(a);
  std::printf("SNR at level 100: %s\n", decimal(a.snr_level100).c_str());
  if (a.velocity_distribution) print_worst_velocity(a);
  std::printf("Snapshot SNR at level 100: %s\n", decimal(a.snapshot_snr_level100).c_str());
  std::printf("Ratio to the snapshot: %s\n", decimal(a.ratio_to_snapshot).c_str());
  print_regularization_and_bound(a, averaged);
}

// With an ADC, a warning when the mean level-100 readout passes the top of its
// range (the figure of merit counts only the rounding, not the clipping).
void warn_adc_range(const fss::CodeAnalysis& a) {
  if (const std::string warning = fss::adc_range_warning(a); !warning.empty()) {
    fss::write_stderr("fssim: warning: " + warning + "\n");
  }
}

}  // namespace

CodeAnalyzeCommand::CodeAnalyzeCommand(CLI::App& code)
    : Command(code, "analyze",
              "figures of merit of a code without simulating an image: sums, min "
              "|K|, M, SNR at level 100 (the stationary, image-independent "
              "figure of merit) and its ratio to the snapshot's") {
  CLI::App& analyze = app();
  analyze
      .add_option("CODE", code_,
                  "a built-in code (snapshot, accumulation, raskar, random, mip, sinc) or a "
                  "code file")
      ->required();
  velocity_option_ =
      analyze.add_option("-v,--velocity", velocity_, "velocity in pixels per time slot")
          ->check(finite())
          ->capture_default_str();
  add_velocity_distribution_option(&analyze, &velocity_distribution_,
                                   &velocity_distribution_option_);
  analyze.add_option("--dt", dt_, "time slot length, > 0")->check(scale())->capture_default_str();
  analyze.add_option("--snr", snr_, "SNR of a level-100 landscape seen through one slot")
      ->check(scale())
      ->capture_default_str();
  analyze.add_option("-m,--mode", mode_, "numerical or analog (Q and admissible gains)")
      ->check(CLI::IsMember({"numerical", "analog"}))
      ->capture_default_str();
  analyze
      .add_option("--grid", grid_,
                  "M on the N-point DFT grid (the simulator uses N = 2 (W - B): the SNR at "
                  "level 100 is then the simulator's stationary figure of merit); 0: an " +
                      std::to_string(2 * fss::kBandGridPoints) +
                      "-node midpoint rule; N <= " + std::to_string(fss::kMaxAnalysisGridPoints))
      ->check(integer_in(0, fss::kMaxAnalysisGridPoints))
      ->capture_default_str();
  sensor_.Add(&analyze);
  restoration_.Add(&analyze);
  analyze.add_option("--json", json_,
                     "also write the analysis as JSON to this file (-: standard output, "
                     "instead of the text)");
}

int CodeAnalyzeCommand::Run() const {
  const std::optional<fss::VelocityDistribution> velocities = design_velocity_distribution(
      velocity_distribution_option_, velocity_distribution_, velocity_option_, dt_);
  const fss::ShutterCode code = fss::load_code(code_);
  const fss::ShutterMode mode = *fss::shutter_mode_from_string(mode_);
  // The code is checked as the simulator checks it (fss::check_code_for_mode).
  const fss::SensorModel sensor = sensor_.Model("code analyze");
  const fss::RestorationOptions restoration = restoration_.Options();
  if (grid_ != 0 && restoration.method != fss::RestorationMethod::kInverse) {
    fss::throw_usage_error(
        "--grid " + std::to_string(grid_) +
        ": the DFT grid is the inverse filter's (the simulator's M); --restoration " +
        fss::to_string(restoration.method) + " uses the midpoint rule");
  }
  const fss::CodeAnalysis a =
      velocities ? fss::analyze_code(code, *velocities, dt_, snr_, mode, grid_, sensor, restoration)
                 : fss::analyze_code(code, velocity_, dt_, snr_, mode, grid_, sensor, restoration);
  warn_adc_range(a);
  if (!json_.empty()) {
    std::vector<std::string> inputs = {code_};
    if (velocities && velocities->kind == fss::VelocityDistributionKind::kDiscrete) {
      inputs.push_back(velocity_distribution_);
    }
    write_output(json_, analysis_json(code, a).dump(2) + "\n", inputs);
  }
  if (!is_stdout(json_)) print_analysis(code, a, mode_);  // else stdout is the JSON
  return kExitSuccess;
}

}  // namespace fssim
