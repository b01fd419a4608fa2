// The code tools: fss.analyze_code, generate_code, optimize_code,
// transfer_function, read_code, builtin_codes.
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
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"

namespace fss::python {
namespace {

namespace args = fss::python;

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

}  // namespace

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
  m.def("builtin_codes", &fss::builtin_code_names, "Names of the built-in codes.");
}

}  // namespace fss::python
