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
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/simulate.h"
#include "simulate_docs.h"

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
  py::dict trial_metrics;       // name -> float64 array, one value a trial
  std::string summary;          // for __repr__
};

void set_number(py::dict& section, const char* key, double value) {
  section[key] = float_object(value);
}

void set_optional(py::dict& section, const char* key, const std::optional<double>& value) {
  if (section.contains(key)) section[key] = optional_float_object(value);
}

// report.json's numbers that JSON writes as null when infinite or NaN, as
// Python floats (inf, nan); None stays where a value does not apply
// (docs/report-schema.md): snr_level100 of a restoration other than the
// inverse filter, an SSIM without pixels, a section's optional field.
void restore_non_finite(const fss::SimulationReport& r, py::dict& d) {
  py::dict metrics = d["metrics"];
  set_number(metrics, "rmse", r.metrics.rmse);
  set_number(metrics, "psnr", r.metrics.psnr);
  set_number(metrics, "rmse_ci", r.metrics.rmse_ci);
  set_number(metrics, "psnr_ci", r.metrics.psnr_ci);
  set_optional(metrics, "ssim", r.metrics.ssim);
  py::dict prediction = d["prediction"];
  const fss::Prediction& p = r.prediction;
  set_number(prediction, "rmse_noise_free", p.rmse_noise_free);
  set_number(prediction, "noise", p.noise);
  set_number(prediction, "rmse", p.rmse);
  set_number(prediction, "sigma", p.sigma);
  set_number(prediction, "rmse_stationary", p.rmse_stationary);
  set_number(prediction, "m", p.m_amplification);
  if (r.options.restoration.method == fss::RestorationMethod::kInverse) {
    set_number(prediction, "snr_level100", p.snr_level100);
  }
  set_optional(prediction, "mse", p.mse);
  py::dict trials = d["trials"];
  set_number(trials, "rmse_mean", r.trials.rmse_mean);
  set_number(trials, "rmse_sd", r.trials.rmse_sd);
  set_number(trials, "rmse_ci_mean", r.trials.rmse_ci_mean);
  set_number(trials, "rmse_ci_sd", r.trials.rmse_ci_sd);
  set_optional(trials, "ssim_mean", r.trials.ssim_mean);
  set_optional(trials, "ssim_sd", r.trials.ssim_sd);
  set_optional(trials, "mse_mean", r.trials.mse_mean);
  set_optional(trials, "mse_sd", r.trials.mse_sd);
  if (d.contains("restoration")) {
    py::dict restoration = d["restoration"];
    set_optional(restoration, "regularization", r.restoration.regularization);
    set_optional(restoration, "prior_level", r.restoration.prior_level);
    set_optional(restoration, "noise_variance", r.restoration.noise_variance);
  }
}

// report.json as a dict, its non-finite numbers as floats.
py::dict report_dict(const fss::SimulationReport& report, const std::string& json_text) {
  py::dict d = py::module_::import("json").attr("loads")(json_text);
  restore_non_finite(report, d);
  return d;
}

// Each trial's metrics (trial t, seed + t, at index t) as float64 arrays:
// rmse, psnr, rmse_ci, psnr_ci, mse (rmse squared), and ssim when every trial has one.
py::dict trial_metrics_dict(const std::vector<fss::Metrics>& trials) {
  const std::size_t n = trials.size();
  std::vector<double> rmse(n), psnr(n), rmse_ci(n), psnr_ci(n), mse(n), ssim(n);
  bool has_ssim = n > 0;
  for (std::size_t t = 0; t < n; ++t) {
    rmse[t] = trials[t].rmse;
    psnr[t] = trials[t].psnr;
    rmse_ci[t] = trials[t].rmse_ci;
    psnr_ci[t] = trials[t].psnr_ci;
    mse[t] = trials[t].rmse * trials[t].rmse;
    has_ssim = has_ssim && trials[t].ssim.has_value();
    ssim[t] = trials[t].ssim.value_or(0.0);
  }
  py::dict d;
  d["rmse"] = array_from_vector(rmse);
  d["psnr"] = array_from_vector(psnr);
  d["rmse_ci"] = array_from_vector(rmse_ci);
  d["psnr_ci"] = array_from_vector(psnr_ci);
  d["mse"] = array_from_vector(mse);
  if (has_ssim) d["ssim"] = array_from_vector(ssim);
  return d;
}

// One line for __repr__: "<fss.SimulationResult code 'raskar', velocity 1, snr 100, 1 trial:
// rmse 4.904 (predicted 4.873), psnr 34.32 dB, restored 64 x 324, 0 warnings>".
std::string result_summary(const fss::SimulationReport& r) {
  const fss::SimulationOptions& o = r.options;
  const std::string velocity = o.velocity_distribution
                                   ? "velocity ~ " + o.velocity_distribution->text()
                                   : "velocity " + fss::format_number(o.velocity_px_per_slot);
  return "<fss.SimulationResult code '" + fss::shorten_for_message(r.code_name) + "', " + velocity +
         ", snr " + fss::format_number(o.snr) + ", " + std::to_string(o.trials) +
         (o.trials == 1 ? " trial" : " trials") + ": rmse " +
         fss::format_number(r.metrics.rmse, 4) + " (predicted " +
         fss::format_number(r.prediction.rmse, 4) + "), psnr " +
         fss::format_number(r.metrics.psnr, 4) + " dB, restored " +
         std::to_string(r.restored.height) + " x " + std::to_string(r.restored.width) +
         (r.channels == 3 ? " x 3" : "") + ", " + std::to_string(r.warnings.size()) +
         (r.warnings.size() == 1 ? " warning>" : " warnings>");
}

// Every warning of the run as an fss.FssimWarning, as fssim prints them.
void warn_all(const fss::SimulationReport& report) {
  for (const std::string& warning : report.warnings) warn(warning);
}

// The result of `report`, whose images it takes.
SimulationResult make_result(fss::SimulationReport& report, const fss::Image& input) {
  fss::Image groundtruth;
  std::string json_text;
  {
    py::gil_scoped_release release;
    groundtruth = fss::groundtruth_image(input, report);
    json_text = fss::report_json_text(report, "");
  }
  SimulationResult result;
  result.report = report_dict(report, json_text);
  result.metrics = result.report["metrics"];
  result.prediction = result.report["prediction"];
  result.geometry = result.report["geometry"];
  result.trials = result.report["trials"];
  result.parameters = result.report["parameters"];
  result.code = result.report["code"];
  result.kernel = result.report["kernel"];
  result.warnings = result.report["warnings"];
  result.trial_velocities = array_from_vector(report.trial_velocities);
  result.trial_metrics = trial_metrics_dict(report.trial_metrics);
  result.summary = result_summary(report);
  result.observed = array_from_image(std::move(report.observed));
  result.restored = array_from_image(std::move(report.restored));
  result.groundtruth = array_from_image(std::move(groundtruth));
  return result;
}

// The keywords of fss.simulate, as Python objects.
struct SimulateCall {
  py::object image, data_range, code, mode, velocity, snr, dt, seed, trials, noise,
      restore_velocity, threads, rmse_margin, max_memory, read_noise, dark_current, full_well,
      adc_bits, adc_gain, restoration, regularization, prior, velocity_distribution;
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

// A warning when the gray levels leave 0..255: the image's values leave [0, data_range], so
// data_range may not be the scale the image was made on.
void warn_outside_range(const fss::Image& image, double data_range) {
  if (image.data.empty()) return;
  const auto [low, high] = std::minmax_element(image.data.begin(), image.data.end());
  if (*low >= 0.0 && *high <= 255.0) return;
  const double to_value = data_range / 255.0;
  warn("image: values from " + fss::format_number(*low * to_value) + " to " +
       fss::format_number(*high * to_value) + " leave [0, data_range] = [0, " +
       fss::format_number(data_range) + "] (gray levels " + fss::format_number(*low) + " to " +
       fss::format_number(*high) + "): is data_range the image's scale?");
}

// The run once the options, the code and the array's shape are checked. A
// float64 copy of an array of another dtype (readable) is freed before the
// run starts: with the image it takes 16 bytes a sample, less than the run
// itself (the image and at least two outputs).
SimulationResult run_simulation(const ImageArgument& image, const fss::SimulationOptions& options,
                                const fss::ShutterCode& code) {
  fss::Image input = image_from_argument(image, "image");
  warn_outside_range(input, image.data_range);
  fss::SimulationReport report;
  {
    py::gil_scoped_release release;
    report = fss::Simulate(options, input, code);
  }
  SimulationResult result = make_result(report, input);
  warn_all(report);
  return result;
}

SimulationResult simulate(const SimulateCall& call) {
  const fss::SimulationOptions options = args::simulation_options(simulate_arguments(call));
  const fss::ShutterCode code = code_from_object(call.code);
  const ImageArgument image = image_array_argument(call.image, call.data_range, "image");
  const args::ImageSize size = image.size;
  args::check_simulation_memory(options, code, size);  // before any copy of the array
  try {
    return run_simulation(image, options, code);
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
  // 8 and 16 as numbers too, as write_png's bit_depth.
  const bool number = py::isinstance<py::int_>(c.png_depth) && !PyBool_Check(c.png_depth.ptr());
  const std::string depth = number ? std::to_string(int_argument(c.png_depth, "png_depth"))
                                   : string_argument(c.png_depth, "png_depth");
  if (depth == "auto") {
    run.image_depth_from_input = true;
  } else if (const auto bits = fss::png_depth_from_string(depth)) {
    run.outputs.image_depth = *bits;
  } else {
    fss::throw_usage_error("png_depth = '" + fss::escape_control_characters(depth) +
                           "': expected 8, 16, '8', '16' or 'auto'");
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
py::dict simulate_to_folder(const SimulateCall& call, const FolderCall& folder) {
  const fss::SimulationOptions options = args::simulation_options(simulate_arguments(call));
  const std::string input = path_argument(call.image, "input");
  const std::string outdir = path_argument(folder.outdir, "outdir");
  const fss::FolderRunOptions run = folder_run_options(folder, call.code);
  const fss::ShutterCode code = code_from_object(call.code);
  std::string json_text;
  fss::SimulationReport report;
  {
    py::gil_scoped_release release;
    report = fss::SimulateToFolder(input, code, outdir, options, run);
    json_text = fss::report_json_text(report, input);
  }
  py::dict result = report_dict(report, json_text);
  warn_all(report);
  return result;
}

// A SimulationResult as a tuple of its fields, and back (pickle: results returned by the
// processes of multiprocessing or concurrent.futures).
py::tuple result_state(const SimulationResult& r) {
  return py::make_tuple(r.observed, r.restored, r.groundtruth, r.report, r.metrics, r.prediction,
                        r.geometry, r.trials, r.parameters, r.code, r.kernel, r.warnings,
                        r.trial_velocities, r.trial_metrics, r.summary);
}

SimulationResult result_from_state(const py::tuple& t) {
  if (t.size() != 15) throw py::value_error("SimulationResult: not a pickled SimulationResult");
  SimulationResult r;
  r.observed = t[0];
  r.restored = t[1];
  r.groundtruth = t[2];
  r.report = t[3].cast<py::dict>();
  r.metrics = t[4];
  r.prediction = t[5];
  r.geometry = t[6];
  r.trials = t[7];
  r.parameters = t[8];
  r.code = t[9];
  r.kernel = t[10];
  r.warnings = t[11];
  r.trial_velocities = t[12];
  r.trial_metrics = t[13].cast<py::dict>();
  r.summary = t[14].cast<std::string>();
  return r;
}

void define_result(py::module_& m) {
  using R = SimulationResult;
  py::class_<R>(m, "SimulationResult", kSimulationResultDoc)
      .def_readonly("observed", &R::observed,
                    "The first trial's observation divided by K(0), float64 gray levels.")
      .def_readonly("restored", &R::restored, "The first trial's restoration, float64 gray levels.")
      .def_readonly("groundtruth", &R::groundtruth, "The input on the output crop, float64.")
      .def_readonly("report", &R::report, "All of report.json as a dict.")
      .def_readonly("metrics", &R::metrics,
                    "The first trial's 'rmse', 'psnr', 'rmse_ci', 'psnr_ci', 'ssim'.")
      .def_readonly("prediction", &R::prediction,
                    "The predicted error: 'finite', 'rmse', 'rmse_noise_free', 'noise', "
                    "'sigma', 'rmse_stationary', 'snr_level100', 'window_mean', 'q', 'm', ...")
      .def_readonly("geometry", &R::geometry,
                    "'blur_length', 'observed_width', 'mirror_width', 'output_width', "
                    "'output_first_input_column', 'rmse_columns', 'rmse_ci_columns'.")
      .def_readonly("trials", &R::trials,
                    "Over the trials: 'n', 'rmse_mean', 'rmse_sd', 'rmse_ci_mean', "
                    "'rmse_ci_sd', 'ssim_mean', 'ssim_sd' (+ 'mse_mean', 'mse_sd', "
                    "'velocities' under a velocity distribution).")
      .def_readonly("trial_metrics", &R::trial_metrics,
                    "Each trial's 'rmse', 'psnr', 'rmse_ci', 'psnr_ci', 'mse' (and 'ssim'), "
                    "float64 arrays of length trials; trial t at index t.")
      .def_readonly("parameters", &R::parameters,
                    "'code', 'code_length', 'mode', 'velocity', 'restore_velocity', 'dt', "
                    "'snr', 'seed', 'noise', 'trials' (+ 'velocity_distribution').")
      .def_readonly("code", &R::code, "'name', 'gains', 'sum', 'square_sum', 'normalized_l1'.")
      .def_readonly("kernel", &R::kernel,
                    "'k0', 'min_abs', 'min_abs_xi', 'invertible', 'observed_divisor', "
                    "'zero_bins'.")
      .def_readonly("warnings", &R::warnings, "The warnings fssim prints for the run (list).")
      .def_readonly("trial_velocities", &R::trial_velocities,
                    "Each trial's velocity under a velocity distribution (float64 array; empty "
                    "without one).")
      .def("__repr__", [](const R& r) { return r.summary; })
      .def(py::pickle(&result_state, &result_from_state));
}

void define_simulate_only(py::module_& m) {
  m.def(
      "simulate",
      [](const py::object& image, const py::object& data_range, const py::object& code,
         const py::object& mode, const py::object& velocity, const py::object& snr,
         const py::object& dt, const py::object& seed, const py::object& trials,
         const py::object& noise, const py::object& restore_velocity, const py::object& threads,
         const py::object& rmse_margin, const py::object& max_memory, const py::object& read_noise,
         const py::object& dark_current, const py::object& full_well, const py::object& adc_bits,
         const py::object& adc_gain, const py::object& restoration,
         const py::object& regularization, const py::object& prior,
         const py::object& velocity_distribution) {
        return simulate({image,
                         data_range,
                         code,
                         mode,
                         velocity,
                         snr,
                         dt,
                         seed,
                         trials,
                         noise,
                         restore_velocity,
                         threads,
                         rmse_margin,
                         max_memory,
                         read_noise,
                         dark_current,
                         full_well,
                         adc_bits,
                         adc_gain,
                         restoration,
                         regularization,
                         prior,
                         velocity_distribution});
      },
      py::arg("image"), py::kw_only(), py::arg("data_range") = py::none(),
      py::arg("code") = "raskar", py::arg("mode") = "numerical", py::arg("velocity") = py::none(),
      py::arg("snr") = 100.0, py::arg("dt") = 1.0, py::arg("seed") = 0, py::arg("trials") = 1,
      py::arg("noise") = "poisson", py::arg("restore_velocity") = py::none(),
      py::arg("threads") = 0, py::arg("rmse_margin") = py::none(), py::arg("max_memory") = 0,
      py::arg("read_noise") = 0.0, py::arg("dark_current") = 0.0, py::arg("full_well") = py::none(),
      py::arg("adc_bits") = 0, py::arg("adc_gain") = py::none(), py::arg("restoration") = "inverse",
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
        return simulate_to_folder({input,
                                   py::none(),
                                   code,
                                   mode,
                                   velocity,
                                   snr,
                                   dt,
                                   seed,
                                   trials,
                                   noise,
                                   restore_velocity,
                                   threads,
                                   rmse_margin,
                                   max_memory,
                                   read_noise,
                                   dark_current,
                                   full_well,
                                   adc_bits,
                                   adc_gain,
                                   restoration,
                                   regularization,
                                   prior,
                                   velocity_distribution},
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
