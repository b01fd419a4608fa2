// The Python module `fss._fss` (pybind11), which the package `fss`
// (python/fss/__init__.py) exposes: the simulator and the code design functions of the
// library on numpy arrays. docs/python.md documents it.
//
// Conventions of the module (on top of fss/core/image.h):
//  - Images are numpy arrays H x W (gray) or H x W x 3 (RGB) of any real
//    numeric dtype; every value is taken as a gray level on the 0..255 scale,
//    as it is (a uint16 array is not divided by 257 as a 16-bit PNG is).
//  - Result images are float64 arrays of the same layout, neither rounded nor
//    clamped (fssim's PNG files hold them rounded and clamped to 0..255).
//  - The dicts of a simulation are report.json's sections, converted from the
//    very text fssim writes; non-finite values are None there as in JSON.
//  - Arguments: convert.h turns each Python object into a C++ value (a
//    TypeError naming the argument when it has the wrong type);
//    arguments.h checks and converts the values as fssim checks its options.
//  - Errors: fss::Error becomes ValueError (usage errors) or RuntimeError
//    (the rest), with the library's message; a failed allocation becomes
//    MemoryError. Every message is one line.
//  - Every computation runs with the GIL released.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "convert.h"
#include "fss/io/report_json.h"

PYBIND11_MODULE(_fss, m) {
  m.doc() = "fssim, the flutter shutter camera simulator, on numpy arrays";
  m.attr("__version__") = FSS_VERSION_FULL;
  m.attr("REPORT_SCHEMA_VERSION") = fss::kReportSchemaVersion;
  fss::python::register_errors();
  fss::python::define_simulate(m);
  fss::python::define_codes(m);
  fss::python::define_images(m);
}
