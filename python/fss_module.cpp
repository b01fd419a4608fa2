// The Python module `fss` (pybind11): the simulator and the code design
// functions of the library on numpy arrays. docs/python.md documents it.
//
// Conventions of the module (on top of fss/core/image.h):
//  - Images are numpy arrays H x W (gray) or H x W x 3 (RGB) of any real
//    numeric dtype; every value is taken as a gray level on the 0..255 scale,
//    as it is (a uint16 array is not divided by 257 as a 16-bit PNG is).
//  - Result images are float64 arrays of the same layout, neither rounded nor
//    clamped (fssim's PNG files hold them rounded and clamped to 0..255).
//  - The dicts of a simulation are report.json's sections, converted from the
//    very text fssim writes; non-finite values are None there as in JSON.
//  - Arguments: this file turns each Python object into a C++ value (a
//    TypeError naming the argument when it has the wrong type);
//    arguments.h checks and converts the values as fssim checks its options.
//  - Errors: fss::Error becomes ValueError (usage errors) or RuntimeError
//    (the rest), with the library's message; a failed allocation becomes
//    MemoryError. Every message is one line.
//  - Every computation runs with the GIL released.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "arguments.h"
#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/io/simulate_to_folder.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/simulate.h"

namespace py = pybind11;
namespace args = fss::python;

namespace {

// An allocation that failed, with what was being done: MemoryError.
class OutOfMemory : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ---------------------------------------------------------------------------
// Python objects as C++ values

[[noreturn]] void throw_type_error(const char* argument, const std::string& expected,
                                   py::handle value) {
  throw py::type_error(
      std::string(argument) + ": expected " + expected + ", not " +
      fss::shorten_for_message(py::type::of(value).attr("__name__").cast<std::string>()));
}

// repr(value), short and on one line, for a message.
std::string short_repr(py::handle value) {
  return fss::shorten_for_message(py::repr(value).cast<std::string>());
}

// A real number: float, int, numpy scalars and size-1 arrays (anything
// float() takes but complex numbers and text).
double float_argument(py::handle value, const char* argument) {
  const bool complex = PyComplex_Check(value.ptr()) != 0 ||
                       (py::hasattr(value, "dtype") &&
                        py::getattr(value, "dtype").attr("kind").cast<std::string>() == "c");
  if (complex || PyUnicode_Check(value.ptr()) != 0 || PyBytes_Check(value.ptr()) != 0) {
    throw_type_error(argument, "a real number", value);
  }
  const double result = PyFloat_AsDouble(value.ptr());
  if (result == -1.0 && PyErr_Occurred() != nullptr) {
    if (PyErr_ExceptionMatches(PyExc_TypeError) != 0) {
      PyErr_Clear();
      throw_type_error(argument, "a real number", value);
    }
    if (PyErr_ExceptionMatches(PyExc_OverflowError) != 0) {
      PyErr_Clear();
      throw py::value_error(std::string(argument) + " = " + short_repr(value) +
                            ": too large for a double-precision number");
    }
    throw py::error_already_set();
  }
  return result;
}

std::optional<double> optional_float(py::handle value, const char* argument) {
  if (value.is_none()) return std::nullopt;
  return float_argument(value, argument);
}

// An integer (int, numpy integers, bool: what operator.index takes but
// numpy.bool_) as a Python int.
py::int_ python_int(py::handle value, const char* argument) {
  // numpy.bool_ as an index is deprecated by numpy itself.
  if (py::isinstance(value, py::module_::import("numpy").attr("bool_"))) {
    throw_type_error(argument, "an integer", value);
  }
  PyObject* index = PyNumber_Index(value.ptr());
  if (index == nullptr) {
    if (PyErr_ExceptionMatches(PyExc_TypeError) == 0) throw py::error_already_set();
    PyErr_Clear();
    throw_type_error(argument, "an integer", value);
  }
  return py::reinterpret_steal<py::int_>(index);
}

long long int_argument(py::handle value, const char* argument) {
  const py::int_ number = python_int(value, argument);
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
  if (overflow != 0) {
    throw py::value_error(std::string(argument) + " = " + short_repr(number) +
                          ": too large for a 64-bit integer");
  }
  if (result == -1 && PyErr_Occurred() != nullptr) throw py::error_already_set();
  return result;
}

std::optional<long long> optional_int(py::handle value, const char* argument) {
  if (value.is_none()) return std::nullopt;
  return int_argument(value, argument);
}

// An integer in [0, 2^64 - 1] (seeds, byte counts): "<argument> = <value>:
// must be an integer in [0, 18446744073709551615]<note>" outside.
std::uint64_t uint64_argument(py::handle value, const char* argument, const char* note = "") {
  const py::int_ number = python_int(value, argument);
  if (number < py::int_(0) || number > py::int_(UINT64_MAX)) {
    throw py::value_error(std::string(argument) + " = " + short_repr(number) +
                          ": must be an integer in [0, " + std::to_string(UINT64_MAX) + "]" + note);
  }
  return number.cast<std::uint64_t>();
}

bool bool_argument(py::handle value, const char* argument) {
  const bool numpy_bool = py::isinstance(value, py::module_::import("numpy").attr("bool_"));
  if (!PyBool_Check(value.ptr()) && !numpy_bool) throw_type_error(argument, "True or False", value);
  return PyObject_IsTrue(value.ptr()) == 1;
}

// A str, as UTF-8 (what cannot be encoded as \\uXXXX, for the message).
std::string string_argument(py::handle value, const char* argument) {
  if (!PyUnicode_Check(value.ptr())) throw_type_error(argument, "a str", value);
  PyObject* bytes = PyUnicode_AsEncodedString(value.ptr(), "utf-8", "backslashreplace");
  if (bytes == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::bytes>(bytes).cast<std::string>();
}

// A path (str, bytes or os.PathLike) as the bytes the file system sees
// (os.fsencode), without a NUL byte.
std::string path_argument(py::handle value, const char* argument) {
  const py::module_ os = py::module_::import("os");
  py::object path;
  try {
    path = os.attr("fspath")(value);
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    throw_type_error(argument, "a str, bytes or os.PathLike", value);
  }
  std::string text = os.attr("fsencode")(path).cast<std::string>();
  args::check_no_nul(argument, text);
  return text;
}

// numpy.asarray(value); what numpy cannot make an array of (a ragged list)
// is a ValueError "<argument>: expected <expected> (<numpy's reason>)".
py::array array_argument(py::handle value, const char* argument, const char* expected) {
  try {
    return py::module_::import("numpy").attr("asarray")(value);
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ValueError) && !e.matches(PyExc_TypeError)) throw;
    throw py::value_error(std::string(argument) + ": expected " + expected + " (" +
                          fss::shorten_for_message(py::str(e.value()).cast<std::string>(), 80) +
                          ")");
  }
}

// What arguments.h reads of an array: its memory, shape, strides, dtype.
args::ArrayView view_of(const py::array& array) {
  args::ArrayView view;
  view.data = array.data();
  view.shape.assign(array.shape(), array.shape() + array.ndim());
  view.strides.assign(array.strides(), array.strides() + array.ndim());
  view.kind = array.dtype().kind();
  view.itemsize = static_cast<std::size_t>(array.dtype().itemsize());
  view.native = array.dtype().attr("isnative").cast<bool>();
  view.dtype = py::str(array.dtype()).cast<std::string>();
  return view;
}

// `array` itself when arguments.h reads its dtype, else a float64 copy.
py::array readable(const py::array& array) {
  if (args::is_readable(view_of(array))) return array;
  return array.attr("astype")("float64");
}

// A planar image as an H x W (one channel) or H x W x 3 float64 array.
py::array_t<double> array_from_image(const fss::Image& image) {
  std::vector<py::ssize_t> shape = {image.height, image.width};
  if (image.channels != 1) shape.push_back(image.channels);
  py::array_t<double> array(shape);
  double* target = array.mutable_data();
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < image.channels; ++c) *target++ = image.at(c, y, x);
    }
  }
  return array;
}

py::array_t<double> array_from_vector(const std::vector<double>& values) {
  py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

// `code=`: a built-in name or a code file (str, bytes or os.PathLike), or a
// sequence of gains (named "array" in the report).
fss::ShutterCode code_from_object(const py::object& code) {
  if (py::isinstance<py::str>(code) || py::isinstance<py::bytes>(code) ||
      py::hasattr(code, "__fspath__")) {
    const std::string name = path_argument(code, "code");
    py::gil_scoped_release release;
    return fss::load_code(name);
  }
  const py::array array =
      array_argument(code, "code", "a built-in name, a code file or a sequence of gains");
  args::check_real_dtype(view_of(array), "code");
  if (array.ndim() == 1 && array.shape(0) > fss::kMaxCodeLength) {
    return args::code_from_view(view_of(array));  // refuses it without a copy
  }
  return args::code_from_view(view_of(readable(array)));
}

// ---------------------------------------------------------------------------
// fss.simulate

// What fss.simulate returns.
struct SimulationResult {
  py::object observed, restored, groundtruth;
  py::dict report;  // report.json as a dict
  py::object metrics, prediction, geometry, trials, parameters, code, kernel, warnings;
  py::object trial_velocities;  // float64 array, empty without a velocity distribution
};

SimulationResult make_result(const fss::SimulationReport& report, const fss::Image& input) {
  fss::Image groundtruth;
  std::string json_text;
  {
    py::gil_scoped_release release;
    groundtruth = fss::groundtruth_image(input, report);
    json_text = fss::report_json_text(report, "");
  }
  SimulationResult result;
  result.observed = array_from_image(report.observed);
  result.restored = array_from_image(report.restored);
  result.groundtruth = array_from_image(groundtruth);
  result.report = py::module_::import("json").attr("loads")(json_text);
  result.metrics = result.report["metrics"];
  result.prediction = result.report["prediction"];
  result.geometry = result.report["geometry"];
  result.trials = result.report["trials"];
  result.parameters = result.report["parameters"];
  result.code = result.report["code"];
  result.kernel = result.report["kernel"];
  result.warnings = result.report["warnings"];
  result.trial_velocities = array_from_vector(report.trial_velocities);
  return result;
}

// The keywords of fss.simulate, as Python objects.
struct SimulateCall {
  py::object image, code, mode, velocity, snr, dt, seed, trials, noise, restore_velocity, threads,
      rmse_margin, max_memory, read_noise, dark_current, full_well, adc_bits, adc_gain, restoration,
      regularization, prior, velocity_distribution;
};

args::SimulateArguments simulate_arguments(const SimulateCall& c) {
  args::SimulateArguments a;
  a.mode = string_argument(c.mode, "mode");
  a.velocity_given = !c.velocity.is_none();
  if (a.velocity_given) a.velocity = float_argument(c.velocity, "velocity");
  // A spec or a path (str, bytes or os.PathLike): load_velocity_distribution tells them apart.
  if (!c.velocity_distribution.is_none()) {
    a.velocity_distribution = path_argument(c.velocity_distribution, "velocity_distribution");
  }
  a.snr = float_argument(c.snr, "snr");
  a.dt = float_argument(c.dt, "dt");
  a.seed = uint64_argument(c.seed, "seed");
  a.trials = int_argument(c.trials, "trials");
  a.noise = string_argument(c.noise, "noise");
  a.restore_velocity = optional_float(c.restore_velocity, "restore_velocity");
  a.threads = int_argument(c.threads, "threads");
  if (py::isinstance<py::str>(c.rmse_margin)) {
    if (string_argument(c.rmse_margin, "rmse_margin") != "auto") {
      fss::throw_usage_error("rmse_margin: a string must be 'auto' (or give a number of columns)");
    }
    a.rmse_margin_auto = true;
  } else {
    a.rmse_margin = optional_int(c.rmse_margin, "rmse_margin");
  }
  a.max_memory = uint64_argument(c.max_memory, "max_memory", " (bytes; 0: no limit)");
  a.read_noise = float_argument(c.read_noise, "read_noise");
  a.dark_current = float_argument(c.dark_current, "dark_current");
  a.full_well = optional_float(c.full_well, "full_well");
  a.adc_bits = int_argument(c.adc_bits, "adc_bits");
  a.adc_gain = optional_float(c.adc_gain, "adc_gain");
  a.restoration = string_argument(c.restoration, "restoration");
  if (py::isinstance<py::str>(c.regularization)) {
    if (string_argument(c.regularization, "regularization") != "optimal") {
      fss::throw_usage_error("regularization: a string must be 'optimal' (or give a number)");
    }
    a.regularization_optimal = true;
  } else {
    a.regularization = optional_float(c.regularization, "regularization");
  }
  if (!c.prior.is_none()) a.prior = string_argument(c.prior, "prior");
  return a;
}

// The run once the options, the code and the array's shape are checked. A
// float64 copy of an array of another dtype (readable) is freed before the
// run starts: with the image it takes 16 bytes a sample, less than the run
// itself (the image and at least two outputs).
SimulationResult run_simulation(const py::array& array, const fss::SimulationOptions& options,
                                const fss::ShutterCode& code) {
  fss::Image input = args::image_from_view(view_of(readable(array)));
  fss::SimulationReport report;
  {
    py::gil_scoped_release release;
    report = fss::Simulate(options, input, code);
  }
  return make_result(report, input);
}

SimulationResult simulate(const SimulateCall& call) {
  const fss::SimulationOptions options = args::simulation_options(simulate_arguments(call));
  const fss::ShutterCode code = code_from_object(call.code);
  const py::array array =
      array_argument(call.image, "image", "an array of gray levels, H x W or H x W x 3");
  const args::ArrayView view = view_of(array);
  args::check_real_dtype(view, "image");
  const args::ImageSize size = args::image_size(view.shape);
  args::check_simulation_memory(options, code, size);  // before any copy of the array
  try {
    return run_simulation(array, options, code);
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(
        "out of memory while simulating a " + std::to_string(size.width) + " x " +
        std::to_string(size.height) + " x " + std::to_string(size.channels) +
        " image (it needs about " +
        fss::format_bytes(static_cast<double>(args::simulation_memory_bytes(options, code, size))) +
        "; max_memory refuses such a run before it starts)");
  }
}

// ---------------------------------------------------------------------------
// fss.simulate_to_folder

// The outputs' keywords of fss.simulate_to_folder, as Python objects.
struct FolderCall {
  py::object outdir, plots, sheet, report, save_float, png_depth;
};

fss::FolderRunOptions folder_run_options(const FolderCall& c, const py::object& code) {
  fss::FolderRunOptions run;
  run.outputs.plots = bool_argument(c.plots, "plots");
  run.outputs.sheet = bool_argument(c.sheet, "sheet");
  run.outputs.html_report = bool_argument(c.report, "report");
  run.outputs.float_outputs = bool_argument(c.save_float, "save_float");
  const std::string depth = string_argument(c.png_depth, "png_depth");
  if (depth == "auto") {
    run.image_depth_from_input = true;
  } else if (const auto bits = fss::png_depth_from_string(depth)) {
    run.outputs.image_depth = *bits;
  } else {
    fss::throw_usage_error("png_depth = '" + fss::escape_control_characters(depth) +
                           "': expected '8', '16' or 'auto'");
  }
  if (py::isinstance<py::str>(code) || py::isinstance<py::bytes>(code) ||
      py::hasattr(code, "__fspath__")) {
    const std::string name = path_argument(code, "code");
    const std::vector<std::string> builtins = fss::builtin_code_names();
    if (std::find(builtins.begin(), builtins.end(), name) == builtins.end()) {
      run.outputs.other_inputs.push_back(name);  // a code file is never overwritten
    }
  }
  return run;
}

// The run of `fssim --input` from a file into a folder (SimulateToFolder);
// returns report.json as a dict.
py::object simulate_to_folder(const SimulateCall& call, const FolderCall& folder) {
  const fss::SimulationOptions options = args::simulation_options(simulate_arguments(call));
  const std::string input = path_argument(call.image, "input");
  const std::string outdir = path_argument(folder.outdir, "outdir");
  const fss::FolderRunOptions run = folder_run_options(folder, call.code);
  const fss::ShutterCode code = code_from_object(call.code);
  std::string json_text;
  {
    py::gil_scoped_release release;
    const fss::SimulationReport report = fss::SimulateToFolder(input, code, outdir, options, run);
    json_text = fss::report_json_text(report, input);
  }
  return py::module_::import("json").attr("loads")(json_text);
}

// ---------------------------------------------------------------------------
// Codes

// Under a velocity distribution (docs/method.md §13), the names `fssim code analyze --json` gives
// them: the distribution (its parameters.velocity_distribution) in place of the velocity (None),
// and the analysis's kernel_velocity, restoration_error, worst velocity and quadrature.
void add_distribution(const fss::CodeAnalysis& a, py::dict& d) {
  if (!a.velocity_distribution) return;
  const fss::VelocityDistribution& v = *a.velocity_distribution;
  py::dict distribution;
  distribution["spec"] = v.text();
  distribution["description"] = v.describe();
  distribution["low"] = v.low;
  distribution["high"] = v.high;
  if (v.kind == fss::VelocityDistributionKind::kNormal) {
    distribution["mean"] = v.mean;
    distribution["sd"] = v.sd;
  }
  const bool exact = v.kind == fss::VelocityDistributionKind::kDiscrete || v.is_point();
  if (v.kind == fss::VelocityDistributionKind::kDiscrete) {
    py::list points;
    for (const fss::VelocityPoint& p : v.points) {
      py::list point;  // [velocity, weight], as in the JSON
      point.append(p.velocity);
      point.append(p.weight);
      points.append(point);
    }
    distribution["points"] = points;
  }
  py::dict quadrature;
  quadrature["rule"] = exact ? "exact sum" : "adaptive gauss-kronrod 7/15";
  quadrature["relative_tolerance"] = fss::kVelocityQuadratureTolerance;
  quadrature["evaluations"] = a.quadrature_evaluations;
  quadrature["intervals"] = a.quadrature_intervals;
  quadrature["error_estimate"] = a.quadrature_error_estimate;
  quadrature["converged"] = a.quadrature_converged;
  d["velocity"] = py::none();
  d["velocity_distribution"] = distribution;
  d["kernel_velocity"] = a.velocity;
  d["restoration_error"] = std::isfinite(a.restoration_error)
                               ? py::object(py::float_(a.restoration_error))
                               : py::object(py::none());
  d["worst_velocity"] = a.worst_velocity;
  d["worst_snr_level100"] = a.worst_snr_level100;
  d["quadrature"] = quadrature;
}

// A CodeAnalysis as a dict: the names of `fssim code analyze --json`'s
// "analysis" section, and the setting it was made for.
py::dict analysis_dict(const fss::CodeAnalysis& a) {
  const auto finite_or_none = [](double value) -> py::object {
    return std::isfinite(value) ? py::object(py::float_(value)) : py::object(py::none());
  };
  py::dict d;
  d["length"] = a.length;
  d["mode"] = fss::to_string(a.mode);
  d["velocity"] = a.velocity;
  d["dt"] = a.dt;
  d["snr"] = a.snr;
  d["grid"] = a.grid;
  d["sum"] = a.sum;
  d["square_sum"] = a.square_sum;
  d["normalized_l1"] = a.normalized_l1;
  d["k0"] = a.k0;
  d["min_abs"] = a.min_abs;
  d["min_abs_xi"] = a.min_abs_xi;
  d["invertible"] = a.invertible;
  d["q"] = a.q;
  d["m"] = finite_or_none(a.m);
  d["noise_figure"] = finite_or_none(a.noise_figure);
  d["snr_level100"] = a.snr_level100;
  d["snapshot_snr_level100"] = a.snapshot_snr_level100;
  d["ratio_to_snapshot"] = a.ratio_to_snapshot;
  d["snr_level100_bound"] = finite_or_none(a.snr_level100_bound);
  add_distribution(a, d);
  return d;
}

py::dict analyze(const py::object& code_object, const py::object& velocity_object,
                 const py::object& dt_object, const py::object& snr_object,
                 const py::object& mode_object, const py::object& grid_object,
                 const py::object& distribution_object) {
  const bool velocity_given = !velocity_object.is_none();
  const double velocity = velocity_given ? float_argument(velocity_object, "velocity") : 1.0;
  const double dt = float_argument(dt_object, "dt");
  const double snr = float_argument(snr_object, "snr");
  const fss::ShutterMode mode = args::mode_argument(string_argument(mode_object, "mode"));
  const int grid =
      args::int_argument("grid", int_argument(grid_object, "grid"), 0, fss::kMaxAnalysisGridPoints);
  args::check_analysis_arguments(velocity, dt, snr);
  std::optional<fss::VelocityDistribution> distribution;
  if (!distribution_object.is_none()) {
    distribution = args::design_distribution(
        path_argument(distribution_object, "velocity_distribution"), velocity_given, velocity);
  }
  const fss::ShutterCode code = code_from_object(code_object);
  fss::CodeAnalysis analysis;
  {
    py::gil_scoped_release release;
    analysis = distribution ? fss::analyze_code(code, *distribution, dt, snr, mode, grid)
                            : fss::analyze_code(code, velocity, dt, snr, mode, grid);
  }
  return analysis_dict(analysis);
}

py::array_t<double> generate(const py::object& family, const py::object& length,
                             const py::object& velocity, const py::object& dt,
                             const py::object& seed, const py::object& analog) {
  const fss::GenerateOptions options =
      args::generate_options(string_argument(family, "family"), int_argument(length, "length"),
                             float_argument(velocity, "velocity"), float_argument(dt, "dt"),
                             uint64_argument(seed, "seed"), bool_argument(analog, "analog"));
  fss::ShutterCode code;
  {
    py::gil_scoped_release release;
    code = fss::generate_code(options);
  }
  return array_from_vector(code.gains);
}

// The keywords of fss.optimize_code, as Python objects.
struct OptimizeCall {
  py::object length, velocity, dt, snr, mode, binary, min_light, restarts, iterations, seed,
      grid_points, velocity_distribution;
};

py::dict optimize(const OptimizeCall& c) {
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
  const fss::OptimizeOptions options = args::optimize_options(a);
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

py::array_t<double> read_png(const py::object& path_object, const py::object& max_memory) {
  const std::string path = path_argument(path_object, "path");
  const std::uint64_t limit = uint64_argument(max_memory, "max_memory", " (bytes; 0: no limit)");
  fss::Image image;
  {
    py::gil_scoped_release release;
    image = fss::read_png(path, static_cast<std::size_t>(std::min<std::uint64_t>(limit, SIZE_MAX)));
  }
  return array_from_image(image);
}

// Sets a Python exception of `type` with `message` on one line, as fssim
// writes its errors: control bytes (a newline in a file name) and bytes that
// are not UTF-8 as \xNN.
void set_error(PyObject* type, const char* message) {
  const std::string line = fss::escape_control_characters(message);
  PyObject* text =
      PyUnicode_DecodeUTF8(line.data(), static_cast<Py_ssize_t>(line.size()), "backslashreplace");
  if (text == nullptr) return;  // the decoding's own error stays set
  PyErr_SetObject(type, text);
  Py_DECREF(text);
}

// pybind11 calls the translator with every C++ exception an exposed function
// lets out (its signature takes the exception_ptr by value).
void register_errors() {
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const fss::Error& e) {
      set_error(e.kind() == fss::ErrorKind::kUsage ? PyExc_ValueError : PyExc_RuntimeError,
                e.what());
    } catch (const OutOfMemory& e) {
      set_error(PyExc_MemoryError, e.what());
    } catch (const std::bad_alloc&) {
      set_error(PyExc_MemoryError,
                "out of memory: an allocation failed (the call needs more memory than the "
                "process may use)");
    } catch (const std::length_error&) {
      set_error(PyExc_MemoryError,
                "out of memory: a buffer larger than the address space was asked for");
    }
  });
}

void define_result(py::module_& m) {
  py::class_<SimulationResult>(m, "SimulationResult",
                               "What fss.simulate returns: the images as float64 arrays and "
                               "report.json's sections as dicts.")
      .def_readonly("observed", &SimulationResult::observed,
                    "observation divided by K(0), output crop (H x Wo [x 3])")
      .def_readonly("restored", &SimulationResult::restored, "restoration, output crop")
      .def_readonly("groundtruth", &SimulationResult::groundtruth, "the input, same crop")
      .def_readonly("report", &SimulationResult::report, "all of report.json")
      .def_readonly("metrics", &SimulationResult::metrics, "report.json's metrics")
      .def_readonly("prediction", &SimulationResult::prediction, "report.json's prediction")
      .def_readonly("geometry", &SimulationResult::geometry, "report.json's geometry")
      .def_readonly("trials", &SimulationResult::trials, "report.json's trials")
      .def_readonly("parameters", &SimulationResult::parameters, "report.json's parameters")
      .def_readonly("code", &SimulationResult::code, "report.json's code")
      .def_readonly("kernel", &SimulationResult::kernel, "report.json's kernel")
      .def_readonly("warnings", &SimulationResult::warnings, "report.json's warnings")
      .def_readonly("trial_velocities", &SimulationResult::trial_velocities,
                    "each trial's velocity under a velocity distribution (float64 array; empty "
                    "without one)")
      .def("__repr__", [](const SimulationResult& r) {
        return "<fss.SimulationResult rmse=" + py::repr(r.metrics["rmse"]).cast<std::string>() +
               " restored shape " + py::repr(r.restored.attr("shape")).cast<std::string>() + ">";
      });
}

// The numpydoc Parameters entries the simulations share (fss.simulate, fss.simulate_to_folder).
constexpr const char* kSimulationParameters =
    R"(code : str, path or sequence of float, default "raskar"
    A built-in code name, a code file, or the gains.
mode : {"numerical", "analog"}, default "numerical"
velocity : float, optional
    The velocity in pixels per time slot (any sign); None is 1. Refused together with
    `velocity_distribution`.
snr : float, default 100
dt : float, default 1
    The time slot length.
seed : int, default 0
    Trial t draws its noise (and, under a distribution, its velocity) from seed + t.
trials : int, default 1
noise : {"poisson", "aggregated", "none"}, default "poisson"
restore_velocity : float, optional
    The velocity the restoration assumes; None: the true one (each trial's under a
    distribution).
threads : int, default 0
    0: all hardware threads; never changes a result.
rmse_margin : int or 'auto', optional
    Columns left out at each side for the RMSE; None: 3 B; 'auto': 3 B where the image is
    wide enough (W >= 9 B + 1), else the largest margin leaving a window of B columns.
max_memory : int, default 0
    Bytes; refuses, before allocating, a run estimated to need more (0: no limit).
read_noise, dark_current : float, default 0
    The sensor (docs/method.md §10): electrons RMS per readout, electrons per slot.
full_well : float, optional
    Electrons; None: none.
adc_bits : int, default 0
    0: no ADC.
adc_gain : float, optional
    Electrons per count (default 1); only with `adc_bits`.
restoration : {"inverse", "tikhonov", "wiener"}, default "inverse"
    docs/method.md §12; ``report["restoration"]`` says what was applied.
regularization : float or "optimal", optional
    Tikhonov's lambda in [1e-8, 1e2]; None or "optimal": the lambda minimising the run's exact
    expected error. `restoration` "tikhonov" only.
prior : str, optional
    Wiener's prior: "power-law", "power-law:GAMMA" or "oracle" (None: "power-law:2").
    `restoration` "wiener" only.
velocity_distribution : str or path, optional
    A distribution of velocities (docs/method.md §13), as ``fssim --velocity-distribution``:
    "uniform:LO:HI", "normal:MEAN:SD" (truncated at MEAN +/- 4 SD and renormalised),
    "normal:MEAN:SD:LO:HI" (truncated), or the path of a file of "velocity weight" lines (a
    discrete distribution, weights normalised). Each trial draws its velocity from it, from
    `seed` and its index only (never from `threads`); the restoration uses the drawn velocity
    unless `restore_velocity` is given; the geometry is that of the support's largest
    |velocity|, the same for every trial. The restorations a distribution allows are the
    library's (SimulationOptions::IsValid): a refused one is a ValueError. Refused with
    `velocity`.
)";

constexpr const char* kSimulationRaises = R"(
Raises
------
ValueError
    A usage error of the library (an option out of range, a code the mode cannot use, an
    image too narrow, a velocity distribution that does not parse or is given with
    `velocity`), one line naming the keyword.
TypeError
    An argument of the wrong type.
RuntimeError
    A file that cannot be read (a velocity file that does not parse included), the memory
    limit.
MemoryError
    A failed allocation.
)";

std::string simulate_doc() {
  return std::string(R"(Simulate a flutter shutter run on `image`, as ``fssim --input`` does.

Every number is checked as fssim checks its option (a ValueError naming the keyword).

Parameters
----------
image : array_like
    H x W (gray) or H x W x 3 (RGB), any real dtype; every value is a gray level on the
    0..255 scale, as it is.
)") + kSimulationParameters +
         R"(
Returns
-------
SimulationResult
    The observed, restored and ground truth crops (float64) and the sections of report.json
    as dicts. Under a velocity distribution, ``trial_velocities`` holds each trial's velocity,
    ``trials["mse_mean"]`` and ``trials["mse_sd"]`` the trials' mean and sample sd of MSE,
    and ``prediction["mse"]`` the exact E[MSE] over the distribution, which ``mse_mean``
    estimates (``prediction["rmse"]`` is its square root, above the mean RMSE).
)" + kSimulationRaises;
}

std::string simulate_to_folder_doc() {
  return std::string(R"(Run ``fssim --input INPUT --outdir OUTDIR`` from Python.

Reads the image file, simulates and writes the same files, byte for byte, all of them or
none. `max_memory` refuses a run from the PNG header, before decoding.

Parameters
----------
input : str or path
    A PNG or TIFF file.
outdir : str or path
    The output folder.
)") + kSimulationParameters +
         R"(plots, sheet, report, save_float : bool
    As --no-plots (negated), --sheet, --report and --save-float.
png_depth : {"8", "16", "auto"}, default "8"

Returns
-------
dict
    report.json (under a velocity distribution with the distribution, each trial's velocity,
    ``trials["mse_mean"]``, ``trials["mse_sd"]`` and ``prediction["mse"]``).
)" + kSimulationRaises;
}

void define_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](const py::object& image, const py::object& code, const py::object& mode,
         const py::object& velocity, const py::object& snr, const py::object& dt,
         const py::object& seed, const py::object& trials, const py::object& noise,
         const py::object& restore_velocity, const py::object& threads,
         const py::object& rmse_margin, const py::object& max_memory, const py::object& read_noise,
         const py::object& dark_current, const py::object& full_well, const py::object& adc_bits,
         const py::object& adc_gain, const py::object& restoration,
         const py::object& regularization, const py::object& prior,
         const py::object& velocity_distribution) {
        return simulate({image,        code,
                         mode,         velocity,
                         snr,          dt,
                         seed,         trials,
                         noise,        restore_velocity,
                         threads,      rmse_margin,
                         max_memory,   read_noise,
                         dark_current, full_well,
                         adc_bits,     adc_gain,
                         restoration,  regularization,
                         prior,        velocity_distribution});
      },
      py::arg("image"), py::kw_only(), py::arg("code") = "raskar", py::arg("mode") = "numerical",
      py::arg("velocity") = py::none(), py::arg("snr") = 100.0, py::arg("dt") = 1.0,
      py::arg("seed") = 0, py::arg("trials") = 1, py::arg("noise") = "poisson",
      py::arg("restore_velocity") = py::none(), py::arg("threads") = 0,
      py::arg("rmse_margin") = py::none(), py::arg("max_memory") = 0, py::arg("read_noise") = 0.0,
      py::arg("dark_current") = 0.0, py::arg("full_well") = py::none(), py::arg("adc_bits") = 0,
      py::arg("adc_gain") = py::none(), py::arg("restoration") = "inverse",
      py::arg("regularization") = py::none(), py::arg("prior") = py::none(),
      py::arg("velocity_distribution") = py::none(), simulate_doc().c_str());
}

void define_simulate_to_folder(py::module_& m) {
  m.def(
      "simulate_to_folder",
      [](const py::object& input, const py::object& outdir, const py::object& code,
         const py::object& mode, const py::object& velocity, const py::object& snr,
         const py::object& dt, const py::object& seed, const py::object& trials,
         const py::object& noise, const py::object& restore_velocity, const py::object& threads,
         const py::object& rmse_margin, const py::object& max_memory, const py::object& read_noise,
         const py::object& dark_current, const py::object& full_well, const py::object& adc_bits,
         const py::object& adc_gain, const py::object& restoration,
         const py::object& regularization, const py::object& prior,
         const py::object& velocity_distribution, const py::object& plots, const py::object& sheet,
         const py::object& report, const py::object& save_float, const py::object& png_depth) {
        return simulate_to_folder({input,        code,
                                   mode,         velocity,
                                   snr,          dt,
                                   seed,         trials,
                                   noise,        restore_velocity,
                                   threads,      rmse_margin,
                                   max_memory,   read_noise,
                                   dark_current, full_well,
                                   adc_bits,     adc_gain,
                                   restoration,  regularization,
                                   prior,        velocity_distribution},
                                  {outdir, plots, sheet, report, save_float, png_depth});
      },
      py::arg("input"), py::arg("outdir"), py::kw_only(), py::arg("code") = "raskar",
      py::arg("mode") = "numerical", py::arg("velocity") = py::none(), py::arg("snr") = 100.0,
      py::arg("dt") = 1.0, py::arg("seed") = 0, py::arg("trials") = 1, py::arg("noise") = "poisson",
      py::arg("restore_velocity") = py::none(), py::arg("threads") = 0,
      py::arg("rmse_margin") = py::none(), py::arg("max_memory") = 0, py::arg("read_noise") = 0.0,
      py::arg("dark_current") = 0.0, py::arg("full_well") = py::none(), py::arg("adc_bits") = 0,
      py::arg("adc_gain") = py::none(), py::arg("restoration") = "inverse",
      py::arg("regularization") = py::none(), py::arg("prior") = py::none(),
      py::arg("velocity_distribution") = py::none(), py::arg("plots") = true,
      py::arg("sheet") = false, py::arg("report") = false, py::arg("save_float") = false,
      py::arg("png_depth") = "8", simulate_to_folder_doc().c_str());
}

constexpr const char* kAnalyzeDoc =
    R"(Figures of merit of a code without an image, as ``fssim code analyze``.

Parameters
----------
code : str, path or sequence of float
    A built-in code name, a code file, or the gains.
velocity : float, optional
    Pixels per time slot; None is 1. Refused together with `velocity_distribution`.
dt : float, default 1
snr : float, default 100
mode : {"numerical", "analog"}, default "numerical"
grid : int, default 0
    Frequencies of M's midpoint rule (0: fssim's default).
velocity_distribution : str or path, optional
    A distribution of velocities (docs/method.md §13), as ``fssim code analyze
    --velocity-distribution``: "uniform:LO:HI", "normal:MEAN:SD" (truncated at MEAN +/- 4 SD
    and renormalised), "normal:MEAN:SD:LO:HI", or the path of a file of "velocity weight"
    lines. The figure of merit is then the expected error over it, each velocity restored at
    itself (adaptive Gauss-Kronrod quadrature to 1e-4 relative; a discrete distribution's exact
    sum), with the worst velocity of the support. Code design needs |v| dt < 2 over the
    support (a ValueError otherwise). Refused with `velocity`.

Returns
-------
dict
    The names of ``fssim code analyze --json``'s "analysis" section, plus the setting (length,
    mode, velocity, dt, snr, grid). Under a distribution, velocity is None and the dict also
    holds velocity_distribution (spec, description, low, high; mean and sd, or points),
    kernel_velocity (the support's largest |v|, where min_abs and invertible are measured),
    restoration_error (the averaged error), worst_velocity, worst_snr_level100 and quadrature.

Raises
------
ValueError
    An argument out of range, a distribution that does not parse or is given with `velocity`,
    a support beyond |v| dt < 2; one line naming the keyword.
TypeError
    An argument of the wrong type.
RuntimeError
    A code or velocity file that cannot be read.
)";

constexpr const char* kOptimizeDoc =
    R"(The code maximizing the SNR at level 100, as ``fssim code optimize``.

Parameters
----------
length : int
velocity : float, optional
    Pixels per time slot, 0 < |velocity| dt < 2. Give it or `velocity_distribution`.
dt : float, default 1
snr : float, default 100
mode : {"numerical", "analog"}, default "numerical"
binary : bool, default False
min_light : float, default 0
    The light budget, sum of gains (analog or binary codes).
restarts, iterations, seed, grid_points : int
    The search's restarts, iterations per start, seed and frequency grid.
velocity_distribution : str or path, optional
    A distribution of velocities (docs/method.md §13), as ``fssim code optimize
    --velocity-distribution``: the search maximizes the SNR of the expected error over it,
    averaged with a fixed composite Gauss-Legendre rule (8 panels of 4 nodes over the support;
    a discrete distribution's own velocities), and the result's analysis is
    ``analyze_code(gains, velocity_distribution=...)``. Refused with `velocity`.

Returns
-------
dict
    gains (float64 array), analysis (as analyze_code), starts, best_start, iterations,
    evaluations.

Raises
------
ValueError
    An argument out of range, neither or both of `velocity` and `velocity_distribution`, a
    distribution that does not parse; one line naming the keyword.
TypeError
    An argument of the wrong type.
RuntimeError
    A velocity file that cannot be read.
)";

void define_codes(py::module_& m) {
  m.def("analyze_code", &analyze, py::arg("code"), py::kw_only(), py::arg("velocity") = py::none(),
        py::arg("dt") = 1.0, py::arg("snr") = 100.0, py::arg("mode") = "numerical",
        py::arg("grid") = 0, py::arg("velocity_distribution") = py::none(), kAnalyzeDoc);
  m.def("generate_code", &generate, py::arg("family"), py::kw_only(), py::arg("length"),
        py::arg("velocity") = 1.0, py::arg("dt") = 1.0, py::arg("seed") = 0,
        py::arg("analog") = false,
        "Gains of a sinc, mip, random, snapshot or accumulation code, as `fssim code generate`.");
  m.def(
      "optimize_code",
      [](const py::object& length, const py::object& velocity, const py::object& dt,
         const py::object& snr, const py::object& mode, const py::object& binary,
         const py::object& min_light, const py::object& restarts, const py::object& iterations,
         const py::object& seed, const py::object& grid_points,
         const py::object& velocity_distribution) {
        return optimize({length, velocity, dt, snr, mode, binary, min_light, restarts, iterations,
                         seed, grid_points, velocity_distribution});
      },
      py::kw_only(), py::arg("length"), py::arg("velocity") = py::none(), py::arg("dt") = 1.0,
      py::arg("snr") = 100.0, py::arg("mode") = "numerical", py::arg("binary") = false,
      py::arg("min_light") = 0.0, py::arg("restarts") = 24, py::arg("iterations") = 300,
      py::arg("seed") = 0, py::arg("grid_points") = 2048,
      py::arg("velocity_distribution") = py::none(), kOptimizeDoc);
  m.def("transfer_function", &transfer, py::arg("code"), py::arg("xi"), py::kw_only(),
        py::arg("velocity") = 1.0, py::arg("dt") = 1.0,
        "K(xi) of a code (complex), xi in radians per pixel: a number or an array.");
  m.def("read_code", &read_code, py::arg("code"),
        "Gains of a built-in code or a code file (float64 array).");
  m.def("read_png", &read_png, py::arg("path"), py::kw_only(), py::arg("max_memory") = 0,
        "A PNG as fssim reads it: float64 gray levels on the 0..255 scale (16-bit / 257). "
        "max_memory (bytes; 0: no limit) refuses a file, or a decoding, that needs more, "
        "before reading it.");
  m.def("builtin_codes", &fss::builtin_code_names, "Names of the built-in codes.");
}

}  // namespace

PYBIND11_MODULE(fss, m) {
  m.doc() = "fssim, the flutter shutter camera simulator, on numpy arrays";
  m.attr("__version__") = FSS_VERSION_FULL;
  m.attr("REPORT_SCHEMA_VERSION") = fss::kReportSchemaVersion;
  register_errors();
  define_result(m);
  define_simulate(m);
  define_simulate_to_folder(m);
  define_codes(m);
}
