// The Python module `fss._fss` (pybind11), which the package `fss`
// (python/fss/__init__.py) exposes: the library on numpy arrays (simulation,
// image files, code design, campaigns). docs/python.md documents it.
//
// Conventions of the module (docs/python.md#conventions):
//  - Numbers: any Python or numpy integer or float scalar; integer parameters
//    also take integral floats; bool is not a number.
//  - Images are numpy arrays H x W (gray) or H x W x 3 (RGB) of any numeric
//    dtype and memory layout, never modified; their scale is explicit:
//    data_range= (gray level = value * 255 / data_range), None for uint8 (255)
//    and uint16 (65535, i.e. / 257 as fssim reads a 16-bit PNG) only.
//  - Result images are float64 arrays on the 0..255 gray-level scale, neither
//    rounded nor clamped; metrics are in gray levels; inf and nan are floats.
//  - Errors: fss::Error becomes ValueError (usage errors) or RuntimeError
//    (the rest), one line naming the Python parameter, never echoing an
//    array; a failed allocation becomes MemoryError. Every warning fssim
//    prints is also a warnings.warn of category fss.FssimWarning.
//  - Each docstring (numpydoc) begins with its text signature; the package
//    fss (python/fss/__init__.py) wraps each function in a Python function
//    carrying it.
//  - Every computation runs with the GIL released.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "convert.h"
#include "fss/io/report_json.h"

PYBIND11_MODULE(_fss, m) {
  // Each docstring begins with its own text signature, "name(sig)\n--\n\n" (the
  // __text_signature__ of a builtin, which inspect.signature reads): pybind11 must not
  // prepend its own.
  pybind11::options options;
  options.disable_function_signatures();
  m.doc() = "fssim, the flutter shutter camera simulator, on numpy arrays";
  m.attr("__version__") = FSS_VERSION_FULL;
  m.attr("REPORT_SCHEMA_VERSION") = fss::kReportSchemaVersion;
  fss::python::register_errors();
  fss::python::register_warnings(m);
  fss::python::define_simulate(m);
  fss::python::define_codes(m);
  fss::python::define_images(m);
  fss::python::define_campaigns(m);
}
