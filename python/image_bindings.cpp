// Image files: fss.read_png.
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
#include "fss/core/image.h"
#include "fss/io/png_io.h"

namespace fss::python {
namespace {

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

}  // namespace

void define_images(py::module_& m) {
  m.def("read_png", &read_png, py::arg("path"), py::kw_only(), py::arg("max_memory") = 0,
        "A PNG as fssim reads it: float64 gray levels on the 0..255 scale (16-bit / 257). "
        "max_memory (bytes; 0: no limit) refuses a file, or a decoding, that needs more, "
        "before reading it.");
}

}  // namespace fss::python
