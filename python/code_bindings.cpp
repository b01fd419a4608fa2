// The code tools: fss.analyze_code, generate_code, optimize_code,
// transfer_function, read_code, builtin_codes (their docstrings: code_docs.h).
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "arguments.h"
#include "bindings.h"
#include "code_docs.h"
#include "convert.h"
#include "design_arguments.h"
#include "fss/core/error.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"

namespace fss::python {
namespace {

namespace args = fss::python;

// ---------------------------------------------------------------------------
// Analyses as dicts: the names of `fssim code analyze --json`, every number a float (inf and nan
// included), None only where a value does not apply.

// Under a velocity distribution (docs/method.md §13): the distribution (its
// parameters.velocity_distribution) in place of the velocity (None), and the analysis's
// kernel_velocity, restoration_error, worst velocity and quadrature.
void add_distribution(const fss::CodeAnalysis& a, py::dict& d) {
  if (!a.velocity_distribution) return;
  const fss::VelocityDistribution& v = *a.velocity_distribution;
  py::dict distribution;
  distribution["spec"] = v.text();
  distribution["description"] = v.describe();
  distribution["low"] = float_object(v.low);
  distribution["high"] = float_object(v.high);
  if (v.kind == fss::VelocityDistributionKind::kNormal) {
    distribution["mean"] = float_object(v.mean);
    distribution["sd"] = float_object(v.sd);
  }
  const bool exact = v.kind == fss::VelocityDistributionKind::kDiscrete || v.is_point();
  if (v.kind == fss::VelocityDistributionKind::kDiscrete) {
    py::list points;
    for (const fss::VelocityPoint& p : v.points) {
      py::list point;  // [velocity, weight], as in the JSON
      point.append(float_object(p.velocity));
      point.append(float_object(p.weight));
      points.append(point);
    }
    distribution["points"] = points;
  }
  py::dict quadrature;
  quadrature["rule"] = exact ? "exact sum" : "adaptive gauss-kronrod 7/15";
  quadrature["relative_tolerance"] = float_object(fss::kVelocityQuadratureTolerance);
  quadrature["evaluations"] = a.quadrature_evaluations;
  quadrature["intervals"] = a.quadrature_intervals;
  quadrature["error_estimate"] = float_object(a.quadrature_error_estimate);
  quadrature["converged"] = a.quadrature_converged;
  d["velocity"] = py::none();
  d["velocity_distribution"] = distribution;
  d["kernel_velocity"] = float_object(a.velocity);
  d["restoration_error"] = float_object(a.restoration_error);
  d["worst_velocity"] = float_object(a.worst_velocity);
  d["worst_snr_level100"] = float_object(a.worst_snr_level100);
  d["quadrature"] = quadrature;
}

// With a sensor (docs/method.md §10): parameters.sensor as "sensor", and the analysis's readouts,
// readout variance and effective Q and noise figure.
void add_sensor(const fss::CodeAnalysis& a, py::dict& d) {
  if (!a.sensor.enabled()) return;
  py::dict sensor;
  sensor["read_noise_electrons"] = float_object(a.sensor.read_noise_electrons);
  sensor["dark_current_electrons_per_slot"] =
      float_object(a.sensor.dark_current_electrons_per_slot);
  sensor["adc_bits"] = a.sensor.adc_bits;
  if (a.sensor.adc_bits != 0) {
    sensor["adc_gain_electrons_per_count"] = float_object(a.sensor.adc_gain_electrons_per_count);
  }
  d["sensor"] = sensor;
  d["readouts"] = float_object(a.readouts);
  d["readout_variance_electrons2"] = float_object(a.readout_variance_electrons2);
  d["effective_q"] = float_object(a.effective_q);
  d["effective_noise_figure"] = float_object(a.effective_noise_figure);
}

// Under a Wiener or Tikhonov restoration (docs/method.md §12): parameters.restoration as
// "restoration" (Tikhonov's lambda None where E is infinite: it has none), and the analysis's
// restoration_error and snapshot_regularization.
void add_restoration(const fss::CodeAnalysis& a, py::dict& d) {
  const fss::RestorationOptions& r = a.restoration;
  if (r.method == fss::RestorationMethod::kInverse) return;
  py::dict restoration;
  restoration["method"] = fss::to_string(r.method);
  restoration["prior"] = "power-law";
  restoration["gamma"] = float_object(r.prior_exponent);
  restoration["C"] = float_object(r.prior_level.value_or(fss::kDefaultPriorLevel));
  if (r.method == fss::RestorationMethod::kTikhonov) {
    restoration["lambda"] = std::isfinite(a.restoration_error)
                                ? py::object(float_object(a.regularization))
                                : py::object(py::none());
    restoration["lambda_optimal"] = !r.regularization.has_value();
    d["snapshot_regularization"] = float_object(a.snapshot_regularization);
  }
  d["restoration"] = restoration;
  d["restoration_error"] = float_object(a.restoration_error);
}

// A CodeAnalysis as a dict: the setting it was made for (length, mode, velocity, dt, snr, grid),
// `fssim code analyze --json`'s "analysis" section, and the parts above.
py::dict analysis_dict(const fss::CodeAnalysis& a) {
  py::dict d;
  d["length"] = a.length;
  d["mode"] = fss::to_string(a.mode);
  d["velocity"] = float_object(a.velocity);
  d["dt"] = float_object(a.dt);
  d["snr"] = float_object(a.snr);
  d["grid"] = a.grid;
  d["sum"] = float_object(a.sum);
  d["square_sum"] = float_object(a.square_sum);
  d["normalized_l1"] = float_object(a.normalized_l1);
  d["k0"] = float_object(a.k0);
  d["min_abs"] = float_object(a.min_abs);
  d["min_abs_xi"] = float_object(a.min_abs_xi);
  d["invertible"] = a.invertible;
  d["q"] = float_object(a.q);
  d["m"] = float_object(a.m);
  d["noise_figure"] = float_object(a.noise_figure);
  d["snr_level100"] = float_object(a.snr_level100);
  d["snapshot_snr_level100"] = float_object(a.snapshot_snr_level100);
  d["ratio_to_snapshot"] = float_object(a.ratio_to_snapshot);
  d["snr_level100_bound"] = float_object(a.snr_level100_bound);
  add_sensor(a, d);
  add_restoration(a, d);
  add_distribution(a, d);
  d["warnings"] = py::list();  // analyze_code adds fssim's warnings
  return d;
}

// ---------------------------------------------------------------------------
// The sensor and restoration keywords of analyze_code and optimize_code

struct DesignCall {
  py::object read_noise, dark_current, adc_bits, adc_gain, full_well, restoration, regularization,
      prior;
};

fss::SensorModel sensor_of(const DesignCall& c) {
  DesignSensorArguments a;
  a.read_noise = float_argument(c.read_noise, "read_noise");
  a.dark_current = float_argument(c.dark_current, "dark_current");
  a.adc_bits = int_argument(c.adc_bits, "adc_bits");
  a.adc_gain = optional_float(c.adc_gain, "adc_gain");
  a.full_well = optional_float(c.full_well, "full_well");
  return design_sensor(a);
}

fss::RestorationOptions restoration_of(const DesignCall& c) {
  DesignRestorationArguments a;
  a.method = string_argument(c.restoration, "restoration");
  if (py::isinstance<py::str>(c.regularization)) {
    const std::string word = string_argument(c.regularization, "regularization");
    if (word != "optimal") {
      throw py::value_error("regularization = '" + fss::shorten_for_message(word) +
                            "': expected a number or 'optimal'");
    }
    a.regularization_optimal = true;
  } else {
    a.regularization = optional_float(c.regularization, "regularization");
  }
  if (!c.prior.is_none()) a.prior = string_argument(c.prior, "prior");
  return design_restoration(a);
}

// ---------------------------------------------------------------------------
// analyze_code

struct AnalyzeCall {
  py::object code, velocity, dt, snr, mode, grid, velocity_distribution;
  DesignCall design;
};

py::dict analyze(const AnalyzeCall& c) {
  const bool velocity_given = !c.velocity.is_none();
  const double velocity = velocity_given ? float_argument(c.velocity, "velocity") : 1.0;
  const double dt = float_argument(c.dt, "dt");
  const double snr = float_argument(c.snr, "snr");
  const fss::ShutterMode mode = args::mode_argument(string_argument(c.mode, "mode"));
  const int grid =
      args::int_argument("grid", int_argument(c.grid, "grid"), 0, fss::kMaxAnalysisGridPoints);
  args::check_analysis_arguments(velocity, dt, snr);
  const fss::SensorModel sensor = sensor_of(c.design);
  const fss::RestorationOptions restoration = restoration_of(c.design);
  check_design_grid(grid, restoration);
  std::optional<fss::VelocityDistribution> distribution;
  if (!c.velocity_distribution.is_none()) {
    distribution = args::design_distribution(
        path_argument(c.velocity_distribution, "velocity_distribution"), velocity_given, velocity);
  }
  const fss::ShutterCode code = code_from_object(c.code);
  fss::CodeAnalysis analysis;
  {
    py::gil_scoped_release release;
    analysis =
        distribution
            ? fss::analyze_code(code, *distribution, dt, snr, mode, grid, sensor, restoration)
            : fss::analyze_code(code, velocity, dt, snr, mode, grid, sensor, restoration);
  }
  py::dict d = analysis_dict(analysis);
  if (const std::string warning = fss::adc_range_warning(analysis); !warning.empty()) {
    warn(warning);
    d["warnings"].cast<py::list>().append(warning);
  }
  return d;
}

// ---------------------------------------------------------------------------
// generate_code

// Refuses a keyword `family` does not use, as `fssim code generate` refuses the option.
void check_family_keyword(const py::object& value, const char* keyword, bool used,
                          const std::string& family) {
  if (value.is_none() || used) return;
  throw py::value_error(std::string(keyword) + ": the " + fss::shorten_for_message(family) +
                        " code does not use it (velocity and dt are for sinc and mip, seed and "
                        "analog for random)");
}

py::array_t<double> generate(const py::object& family, const py::object& length,
                             const py::object& velocity, const py::object& dt,
                             const py::object& seed, const py::object& analog) {
  const fss::GenerateOptions options =
      args::generate_options(string_argument(family, "family"), int_argument(length, "length"),
                             velocity.is_none() ? 1.0 : float_argument(velocity, "velocity"),
                             dt.is_none() ? 1.0 : float_argument(dt, "dt"),
                             seed.is_none() ? 0 : uint64_argument(seed, "seed"),
                             !analog.is_none() && bool_argument(analog, "analog"));
  // The values first (their own errors), then whether the family uses them.
  const bool band =
      options.family == fss::CodeFamily::kSinc || options.family == fss::CodeFamily::kMip;
  const bool random = options.family == fss::CodeFamily::kRandom;
  const std::string name = fss::to_string(options.family);
  check_family_keyword(velocity, "velocity", band, name);
  check_family_keyword(dt, "dt", band, name);
  check_family_keyword(seed, "seed", random, name);
  check_family_keyword(analog, "analog", random, name);
  fss::ShutterCode code;
  {
    py::gil_scoped_release release;
    code = fss::generate_code(options);
  }
  return array_from_vector(code.gains);
}

// ---------------------------------------------------------------------------
// optimize_code

struct OptimizeCall {
  py::object length, velocity, velocity_distribution, dt, snr, mode, binary, min_light, restarts,
      iterations, seed, grid_points;
  DesignCall design;
};

fss::OptimizeOptions optimize_options_of(const OptimizeCall& c) {
  args::OptimizeArguments a;
  a.length = int_argument(c.length, "length");
  a.velocity_given = !c.velocity.is_none();
  if (a.velocity_given) a.velocity = float_argument(c.velocity, "velocity");
  if (!c.velocity_distribution.is_none()) {
    a.velocity_distribution = path_argument(c.velocity_distribution, "velocity_distribution");
  }
  a.dt = float_argument(c.dt, "dt");
  a.snr = float_argument(c.snr, "snr");
  a.mode = string_argument(c.mode, "mode");
  a.binary = bool_argument(c.binary, "binary");
  a.min_light = float_argument(c.min_light, "min_light");
  a.restarts = int_argument(c.restarts, "restarts");
  a.iterations = int_argument(c.iterations, "iterations");
  a.seed = uint64_argument(c.seed, "seed");
  a.grid_points = int_argument(c.grid_points, "grid_points");
  fss::OptimizeOptions options = args::optimize_options(a);
  options.sensor = sensor_of(c.design);
  options.restoration = restoration_of(c.design);
  std::string error;  // the sensor's readout noise at this snr, length and dt
  if (!options.IsValid(&error)) fss::throw_usage_error(design_field_names(error));
  return options;
}

py::dict optimize(const OptimizeCall& c) {
  const fss::OptimizeOptions options = optimize_options_of(c);
  fss::OptimizationResult result;
  {
    py::gil_scoped_release release;
    result = fss::optimize_code(options);
  }
  py::dict d;
  d["gains"] = array_from_vector(result.gains);
  d["analysis"] = analysis_dict(result.analysis);
  d["starts"] = result.starts;
  d["best_start"] = result.best_start;
  d["iterations"] = result.iterations;
  d["evaluations"] = result.evaluations;
  return d;
}

// ---------------------------------------------------------------------------
// transfer_function, read_code

// K(xi) at every frequency of `xi` (radians per pixel), same shape.
py::object transfer(const py::object& code_object, const py::object& xi,
                    const py::object& velocity_object, const py::object& dt_object) {
  const double velocity = float_argument(velocity_object, "velocity");
  const double dt = float_argument(dt_object, "dt");
  const fss::ShutterCode code = code_from_object(code_object);
  const py::array xi_array = array_argument(xi, "xi", "a number or an array of numbers");
  args::check_real_dtype(view_of(xi_array), "xi");
  const std::vector<double> frequencies = args::values_from_view(view_of(readable(xi_array)), "xi");
  const std::vector<py::ssize_t> shape(xi_array.shape(), xi_array.shape() + xi_array.ndim());
  py::array_t<std::complex<double>> values(shape);
  {
    py::gil_scoped_release release;
    args::transfer_values(code, frequencies, velocity, dt,
                          {values.mutable_data(), frequencies.size()});
  }
  if (xi_array.ndim() == 0) return py::cast(*values.data());
  return values;
}

py::array_t<double> read_code(const py::object& name_or_path) {
  return array_from_vector(code_from_object(name_or_path).gains);
}

void define_analyze(py::module_& m) {
  m.def(
      "analyze_code",
      [](const py::object& code, const py::object& velocity, const py::object& dt,
         const py::object& snr, const py::object& mode, const py::object& grid,
         const py::object& velocity_distribution, const py::object& read_noise,
         const py::object& dark_current, const py::object& adc_bits, const py::object& adc_gain,
         const py::object& full_well, const py::object& restoration,
         const py::object& regularization, const py::object& prior) {
        return analyze({code,
                        velocity,
                        dt,
                        snr,
                        mode,
                        grid,
                        velocity_distribution,
                        {read_noise, dark_current, adc_bits, adc_gain, full_well, restoration,
                         regularization, prior}});
      },
      py::arg("code"), py::kw_only(), py::arg("velocity") = py::none(), py::arg("dt") = 1.0,
      py::arg("snr") = 100.0, py::arg("mode") = "numerical", py::arg("grid") = 0,
      py::arg("velocity_distribution") = py::none(), py::arg("read_noise") = 0.0,
      py::arg("dark_current") = 0.0, py::arg("adc_bits") = 0, py::arg("adc_gain") = py::none(),
      py::arg("full_well") = py::none(), py::arg("restoration") = "inverse",
      py::arg("regularization") = py::none(), py::arg("prior") = py::none(), kAnalyzeDoc);
}

void define_optimize(py::module_& m) {
  m.def(
      "optimize_code",
      [](const py::object& length, const py::object& velocity,
         const py::object& velocity_distribution, const py::object& dt, const py::object& snr,
         const py::object& mode, const py::object& binary, const py::object& min_light,
         const py::object& restarts, const py::object& iterations, const py::object& seed,
         const py::object& grid_points, const py::object& read_noise,
         const py::object& dark_current, const py::object& adc_bits, const py::object& adc_gain,
         const py::object& full_well, const py::object& restoration,
         const py::object& regularization, const py::object& prior) {
        return optimize({length,
                         velocity,
                         velocity_distribution,
                         dt,
                         snr,
                         mode,
                         binary,
                         min_light,
                         restarts,
                         iterations,
                         seed,
                         grid_points,
                         {read_noise, dark_current, adc_bits, adc_gain, full_well, restoration,
                          regularization, prior}});
      },
      py::kw_only(), py::arg("length"), py::arg("velocity") = py::none(),
      py::arg("velocity_distribution") = py::none(), py::arg("dt") = 1.0, py::arg("snr") = 100.0,
      py::arg("mode") = "numerical", py::arg("binary") = false, py::arg("min_light") = 0.0,
      py::arg("restarts") = 24, py::arg("iterations") = 300, py::arg("seed") = 0,
      py::arg("grid_points") = 2048, py::arg("read_noise") = 0.0, py::arg("dark_current") = 0.0,
      py::arg("adc_bits") = 0, py::arg("adc_gain") = py::none(), py::arg("full_well") = py::none(),
      py::arg("restoration") = "inverse", py::arg("regularization") = py::none(),
      py::arg("prior") = py::none(), kOptimizeDoc);
}

}  // namespace

void define_codes(py::module_& m) {
  define_analyze(m);
  define_optimize(m);
  m.def("generate_code", &generate, py::arg("family"), py::kw_only(), py::arg("length"),
        py::arg("velocity") = py::none(), py::arg("dt") = py::none(), py::arg("seed") = py::none(),
        py::arg("analog") = py::none(), kGenerateDoc);
  m.def("transfer_function", &transfer, py::arg("code"), py::arg("xi"), py::kw_only(),
        py::arg("velocity") = 1.0, py::arg("dt") = 1.0, kTransferDoc);
  m.def("read_code", &read_code, py::arg("code"), kReadCodeDoc);
  m.def(
      "builtin_codes", [] { return fss::builtin_code_names(); }, kBuiltinCodesDoc);
}

}  // namespace fss::python
