// fss.simulate and fss.simulate_to_folder, and the SimulationResult.
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
#include "bindings.h"
#include "convert.h"
#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/io/simulate_to_folder.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss::python {
namespace {

namespace args = fss::python;

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

void define_simulate_only(py::module_& m) {
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

}  // namespace

void define_simulate(py::module_& m) {
  define_result(m);
  define_simulate_only(m);
  define_simulate_to_folder(m);
}

}  // namespace fss::python
