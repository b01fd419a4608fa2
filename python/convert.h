// Python objects as the C++ values of the module `fss` (pybind11), and the
// module's errors. Each converter raises a TypeError naming the argument when
// the object has the wrong type; arguments.h then checks the values as fssim
// checks its options.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "arguments.h"
#include "fss/core/image.h"
#include "fss/model/code.h"

namespace fss::python {

namespace py = pybind11;

// An allocation that failed, with what was being done: MemoryError.
class OutOfMemory : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void throw_type_error(const char* argument, const std::string& expected,
                                   py::handle value);
std::string short_repr(py::handle value);
double float_argument(py::handle value, const char* argument);
std::optional<double> optional_float(py::handle value, const char* argument);
py::int_ python_int(py::handle value, const char* argument);
long long int_argument(py::handle value, const char* argument);
std::optional<long long> optional_int(py::handle value, const char* argument);
std::uint64_t uint64_argument(py::handle value, const char* argument, const char* note = "");
bool bool_argument(py::handle value, const char* argument);
std::string string_argument(py::handle value, const char* argument);
std::string path_argument(py::handle value, const char* argument);
py::array array_argument(py::handle value, const char* argument, const char* expected);
ArrayView view_of(const py::array& array);
py::array readable(const py::array& array);
py::array_t<double> array_from_image(const fss::Image& image);
py::array_t<double> array_from_vector(const std::vector<double>& values);
fss::ShutterCode code_from_object(const py::object& code);

// Translates the library's exceptions: fss::Error to ValueError (usage) or
// RuntimeError, OutOfMemory and failed allocations to MemoryError.
void register_errors();

}  // namespace fss::python
