// The Python module `fss` (pybind11): the simulator and the code design
// functions of the library on numpy arrays. The README's section "Python"
// documents it.
//
// Conventions of the module (on top of fss/core/image.h):
//  - Images are numpy arrays H x W (gray) or H x W x 3 (RGB) of any real
//    numeric dtype; every value is taken as a gray level on the 0..255 scale,
//    as it is (a uint16 array is not divided by 257 as a 16-bit PNG is).
//  - Result images are float64 arrays of the same layout, neither rounded nor
//    clamped (fssim's PNG files hold them rounded and clamped to 0..255).
//  - The dicts of a simulation are report.json's sections, converted from the
//    very text fssim writes; non-finite values are None there as in JSON.
//  - fss::Error becomes ValueError (usage errors) or RuntimeError (the rest),
//    with the library's message.
//  - Every computation runs with the GIL released.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/model/code.h"
#include "fss/model/sensor.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/simulate.h"

namespace py = pybind11;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// ---------------------------------------------------------------------------
// Arguments

[[noreturn]] void throw_value_error(const std::string& message) { throw py::value_error(message); }

// The dtype kinds accepted for images and gains: bool, signed and unsigned
// integers, floating point.
void check_real_dtype(const py::array& array, const std::string& what) {
  const char kind = array.dtype().kind();
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f') {
    throw_value_error(what + ": dtype " + py::str(array.dtype()).cast<std::string>() +
                      " is not a real numeric type (expected bool, integer or float)");
  }
}

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) {
    text += (d > 0 ? ", " : "") + std::to_string(array.shape(d));
  }
  return text + (array.ndim() == 1 ? ",)" : ")");
}

// An H x W or H x W x C (C = 1 or 3) array as a planar fss::Image:
// data[(c H + y) W + x] = array[y, x, c].
fss::Image image_from_array(const py::array& array) {
  check_real_dtype(array, "image");
  const bool layout_ok =
      array.ndim() == 2 || (array.ndim() == 3 && (array.shape(2) == 1 || array.shape(2) == 3));
  if (!layout_ok) {
    throw_value_error("image: shape " + shape_text(array) +
                      " is not H x W (gray) or H x W x 3 (RGB)");
  }
  const py::ssize_t height = array.shape(0);
  const py::ssize_t width = array.shape(1);
  if (height < 1 || width < 1 || height > fss::kMaxImageSide || width > fss::kMaxImageSide) {
    throw_value_error("image: shape " + shape_text(array) + " must have 1 to " +
                      std::to_string(fss::kMaxImageSide) + " rows and columns");
  }
  const int channels = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  const DoubleArray values = DoubleArray::ensure(array);
  if (!values) throw py::error_already_set();
  fss::Image image(static_cast<int>(width), static_cast<int>(height), channels);
  const double* source = values.data();
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < channels; ++c) {
        const double value = *source++;
        if (!std::isfinite(value)) {
          throw_value_error("image: value " + fss::format_number(value) + " at row " +
                            std::to_string(y) + ", column " + std::to_string(x) + " is not finite");
        }
        image.at(c, y, x) = value;
      }
    }
  }
  return image;
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

// `code=`: a built-in name or a code file (str or os.PathLike), or a
// sequence of gains (named "array" in the report).
fss::ShutterCode code_from_object(const py::object& code) {
  if (py::isinstance<py::str>(code) || py::hasattr(code, "__fspath__")) {
    const std::string name = py::module_::import("os").attr("fspath")(code).cast<std::string>();
    py::gil_scoped_release release;
    return fss::load_code(name);
  }
  const py::array array = py::array::ensure(code);
  if (!array) {
    throw_value_error("code: expected a built-in name, a code file or a sequence of gains");
  }
  check_real_dtype(array, "code");
  if (array.ndim() != 1) {
    throw_value_error("code: gains of shape " + shape_text(array) + " are not one-dimensional");
  }
  const DoubleArray gains = DoubleArray::ensure(array);
  if (!gains) throw py::error_already_set();
  fss::ShutterCode result{"array", std::vector<double>(gains.data(), gains.data() + gains.size())};
  for (const double gain : result.gains) {
    if (!std::isfinite(gain)) {
      throw_value_error("code: gain " + fss::format_number(gain) + " is not finite");
    }
  }
  return result;
}

fss::ShutterMode mode_from_string(const std::string& mode) {
  const std::optional<fss::ShutterMode> parsed = fss::shutter_mode_from_string(mode);
  if (!parsed) throw_value_error("mode: '" + mode + "' is not 'numerical' or 'analog'");
  return *parsed;
}

fss::NoiseModel noise_from_string(const std::string& noise) {
  const std::optional<fss::NoiseModel> parsed = fss::noise_model_from_string(noise);
  if (!parsed) throw_value_error("noise: '" + noise + "' is not 'poisson' or 'none'");
  return *parsed;
}

// A non-negative Python int as a uint64 seed.
std::uint64_t seed_from_int(const py::int_& seed) {
  if (seed < py::int_(0) || seed > py::int_(UINT64_MAX)) {
    throw_value_error("seed: " + py::repr(seed).cast<std::string>() + " must lie in [0, 2^64 - 1]");
  }
  return seed.cast<std::uint64_t>();
}

// ---------------------------------------------------------------------------
// fss.simulate

// What fss.simulate returns.
struct SimulationResult {
  py::object observed, restored, groundtruth;
  py::dict report;  // report.json as a dict
  py::object metrics, prediction, geometry, trials, parameters, code, kernel, warnings;
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
  return result;
}

struct SimulateArguments {
  py::object code;
  std::string mode;
  double velocity;
  double snr;
  double dt;
  py::int_ seed;
  int trials;
  std::string noise;
  std::optional<double> restore_velocity;
  int threads;
  std::optional<int> rmse_margin;
  std::size_t max_memory;
  fss::SensorModel sensor;  // docs/method.md §10
};

// The sensor keywords as a SensorModel (checked by Simulate's rules).
fss::SensorModel sensor_from(double read_noise, double dark_current,
                             std::optional<double> full_well, int adc_bits, double adc_gain) {
  fss::SensorModel sensor;
  sensor.read_noise_electrons = read_noise;
  sensor.dark_current_electrons_per_slot = dark_current;
  sensor.full_well_electrons = full_well;
  sensor.adc_bits = adc_bits;
  sensor.adc_gain_electrons_per_count = adc_gain;
  return sensor;
}

SimulationResult simulate(const py::array& image_array, const SimulateArguments& a) {
  fss::SimulationOptions options;
  options.mode = mode_from_string(a.mode);
  options.velocity_px_per_slot = a.velocity;
  options.restore_velocity_px_per_slot = a.restore_velocity;
  options.snr = a.snr;
  options.dt = a.dt;
  options.seed = seed_from_int(a.seed);
  options.trials = a.trials;
  options.noise = noise_from_string(a.noise);
  options.threads = a.threads;
  options.rmse_margin_columns = a.rmse_margin.value_or(-1);
  options.max_memory_bytes = a.max_memory;
  options.sensor = a.sensor;
  const fss::ShutterCode code = code_from_object(a.code);
  const fss::Image input = image_from_array(image_array);
  fss::SimulationReport report;
  {
    py::gil_scoped_release release;
    report = fss::Simulate(options, input, code);
  }
  return make_result(report, input);
}

// ---------------------------------------------------------------------------
// Codes

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
  return d;
}

py::dict analyze(const py::object& code_object, double velocity, double dt, double snr,
                 const std::string& mode, int grid) {
  const fss::ShutterCode code = code_from_object(code_object);
  const fss::ShutterMode shutter_mode = mode_from_string(mode);
  fss::CodeAnalysis analysis;
  {
    py::gil_scoped_release release;
    analysis = fss::analyze_code(code, velocity, dt, snr, shutter_mode, grid);
  }
  return analysis_dict(analysis);
}

py::array_t<double> generate(const std::string& family, int length, double velocity, double dt,
                             const py::int_& seed, bool analog) {
  fss::GenerateOptions options;
  const std::optional<fss::CodeFamily> parsed = fss::code_family_from_string(family);
  if (!parsed) {
    throw_value_error("family: '" + family +
                      "' is not one of sinc, mip, random, snapshot, accumulation");
  }
  options.family = *parsed;
  options.length = length;
  options.velocity_px_per_slot = velocity;
  options.dt = dt;
  options.seed = seed_from_int(seed);
  options.analog = analog;
  fss::ShutterCode code;
  {
    py::gil_scoped_release release;
    code = fss::generate_code(options);
  }
  return array_from_vector(code.gains);
}

struct OptimizeArguments {
  int length;
  double velocity;
  double dt;
  double snr;
  std::string mode;
  bool binary;
  double min_light;
  int restarts;
  int iterations;
  py::int_ seed;
  int grid_points;
};

py::dict optimize(const OptimizeArguments& a) {
  fss::OptimizeOptions options;
  options.length = a.length;
  options.velocity_px_per_slot = a.velocity;
  options.dt = a.dt;
  options.snr = a.snr;
  options.mode = mode_from_string(a.mode);
  options.binary = a.binary;
  options.min_light_slots = a.min_light;
  options.restarts = a.restarts;
  options.max_iterations = a.iterations;
  options.seed = seed_from_int(a.seed);
  options.grid_points = a.grid_points;
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
py::object transfer(const py::object& code_object, const py::object& xi, double velocity,
                    double dt) {
  const fss::ShutterCode code = code_from_object(code_object);
  const py::array xi_array = py::array::ensure(xi);
  if (!xi_array) throw_value_error("xi: expected a number or an array of numbers");
  check_real_dtype(xi_array, "xi");
  const DoubleArray frequencies = DoubleArray::ensure(xi_array);
  if (!frequencies) throw py::error_already_set();
  std::vector<py::ssize_t> shape(frequencies.shape(), frequencies.shape() + frequencies.ndim());
  py::array_t<std::complex<double>> values(shape);
  const double* in = frequencies.data();
  std::complex<double>* out = values.mutable_data();
  const py::ssize_t count = frequencies.size();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < count; ++i) {
      out[i] = fss::transfer_function(code.gains, velocity, dt, in[i]);
    }
  }
  if (frequencies.ndim() == 0) return py::cast(out[0]);
  return values;
}

py::array_t<double> read_code(const py::object& name_or_path) {
  return array_from_vector(code_from_object(name_or_path).gains);
}

py::array_t<double> read_png(const py::object& path_object) {
  const std::string path =
      py::module_::import("os").attr("fspath")(path_object).cast<std::string>();
  fss::Image image;
  {
    py::gil_scoped_release release;
    image = fss::read_png(path);
  }
  return array_from_image(image);
}

// pybind11 calls the translator with every C++ exception an exposed function
// lets out (its signature takes the exception_ptr by value).
void register_errors() {
  // NOLINTNEXTLINE(performance-unnecessary-value-param)
  py::register_exception_translator([](std::exception_ptr pointer) {
    try {
      if (pointer) std::rethrow_exception(pointer);
    } catch (const fss::Error& e) {
      PyErr_SetString(e.kind() == fss::ErrorKind::kUsage ? PyExc_ValueError : PyExc_RuntimeError,
                      e.what());
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
      .def("__repr__", [](const SimulationResult& r) {
        return "<fss.SimulationResult rmse=" + py::repr(r.metrics["rmse"]).cast<std::string>() +
               " restored shape " + py::repr(r.restored.attr("shape")).cast<std::string>() + ">";
      });
}

void define_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](const py::array& image, const py::object& code, const std::string& mode, double velocity,
         double snr, double dt, const py::int_& seed, int trials, const std::string& noise,
         std::optional<double> restore_velocity, int threads, std::optional<int> rmse_margin,
         std::size_t max_memory, double read_noise, double dark_current,
         std::optional<double> full_well, int adc_bits, double adc_gain) {
        return simulate(
            image, {code, mode, velocity, snr, dt, seed, trials, noise, restore_velocity, threads,
                    rmse_margin, max_memory,
                    sensor_from(read_noise, dark_current, full_well, adc_bits, adc_gain)});
      },
      py::arg("image"), py::kw_only(), py::arg("code") = "raskar", py::arg("mode") = "numerical",
      py::arg("velocity") = 1.0, py::arg("snr") = 100.0, py::arg("dt") = 1.0, py::arg("seed") = 0,
      py::arg("trials") = 1, py::arg("noise") = "poisson", py::arg("restore_velocity") = py::none(),
      py::arg("threads") = 0, py::arg("rmse_margin") = py::none(), py::arg("max_memory") = 0,
      py::arg("read_noise") = 0.0, py::arg("dark_current") = 0.0, py::arg("full_well") = py::none(),
      py::arg("adc_bits") = 0, py::arg("adc_gain") = 1.0,
      "Simulates a flutter shutter run on `image` (H x W or H x W x 3, gray levels on the "
      "0..255 scale) as `fssim --input` does; returns a SimulationResult. The sensor "
      "(docs/method.md §10): read_noise (electrons RMS per readout), dark_current (electrons "
      "per slot), full_well (electrons, None: none), adc_bits (0: no ADC) and adc_gain "
      "(electrons per count); all off by default. With a sensor, result.report['sensor'] "
      "holds them and result.prediction['exact'] says whether the prediction is exact.");
}

void define_codes(py::module_& m) {
  m.def("analyze_code", &analyze, py::arg("code"), py::kw_only(), py::arg("velocity") = 1.0,
        py::arg("dt") = 1.0, py::arg("snr") = 100.0, py::arg("mode") = "numerical",
        py::arg("grid") = 0,
        "Figures of merit of a code without an image, as `fssim code analyze` (dict).");
  m.def("generate_code", &generate, py::arg("family"), py::kw_only(), py::arg("length"),
        py::arg("velocity") = 1.0, py::arg("dt") = 1.0, py::arg("seed") = 0,
        py::arg("analog") = false,
        "Gains of a sinc, mip, random, snapshot or accumulation code, as `fssim code generate`.");
  m.def(
      "optimize_code",
      [](int length, double velocity, double dt, double snr, const std::string& mode, bool binary,
         double min_light, int restarts, int iterations, const py::int_& seed, int grid_points) {
        return optimize({length, velocity, dt, snr, mode, binary, min_light, restarts, iterations,
                         seed, grid_points});
      },
      py::kw_only(), py::arg("length"), py::arg("velocity"), py::arg("dt") = 1.0,
      py::arg("snr") = 100.0, py::arg("mode") = "numerical", py::arg("binary") = false,
      py::arg("min_light") = 0.0, py::arg("restarts") = 24, py::arg("iterations") = 300,
      py::arg("seed") = 0, py::arg("grid_points") = 2048,
      "The code maximizing the SNR at level 100, as `fssim code optimize` (dict).");
  m.def("transfer_function", &transfer, py::arg("code"), py::arg("xi"), py::kw_only(),
        py::arg("velocity") = 1.0, py::arg("dt") = 1.0,
        "K(xi) of a code (complex), xi in radians per pixel: a number or an array.");
  m.def("read_code", &read_code, py::arg("code"),
        "Gains of a built-in code or a code file (float64 array).");
  m.def("read_png", &read_png, py::arg("path"),
        "A PNG as fssim reads it: float64 gray levels on the 0..255 scale (16-bit / 257).");
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
  define_codes(m);
}
