// Python objects as the C++ values of the module `fss` (pybind11), and the
// module's errors. Each converter raises a TypeError naming the argument when
// the object has the wrong type; arguments.h then checks the values as fssim
// checks its options.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
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

// Scalars (docs/python.md): any Python or numpy real scalar or 0-d array where
// a number is expected; integer arguments also take integral floats (3.0);
// bool, complex and str are a TypeError naming the argument.
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

// Images (docs/python.md's data_range rule). The value that stands for gray
// level 255 of `array`: `data_range` when given (a finite number > 0), else 255
// for uint8 and 65535 for uint16; any other dtype needs data_range (ValueError
// naming `argument`).
double data_range_argument(py::handle data_range, const py::array& array, const char* argument);

// An image argument checked but not read yet: the array as given (no copy),
// its size and its data_range.
struct ImageArgument {
  py::array array;
  ImageSize size;
  double data_range = 255.0;
};

// `value` as an image array of H x W or H x W x 3 and its data_range, checked
// from the shape and dtype alone (nothing as large as the image allocated).
ImageArgument image_array_argument(py::handle value, py::handle data_range, const char* argument);
// The checked array's gray levels (value x 255 / data_range) as an fss::Image.
fss::Image image_from_argument(const ImageArgument& image, const char* argument);
// Both: `value` as an fss::Image of gray levels.
fss::Image image_argument(py::handle value, py::handle data_range, const char* argument);

// Outputs
py::array_t<double> array_from_image(const fss::Image& image);
// The same, taking a gray image's buffer without a copy (a color one is copied: planar to H x W x
// 3).
py::array_t<double> array_from_image(fss::Image&& image);
py::array_t<double> array_from_vector(const std::vector<double>& values);
// A number of a result dict: a Python float, inf and nan included (never None).
py::float_ float_object(double value);
// None when the value does not apply (empty), else float_object.
py::object optional_float_object(const std::optional<double>& value);

fss::ShutterCode code_from_object(const py::object& code);

// The library's CLI words as the module's (one place): "--mode numerical" as
// "mode='numerical'", "--rmse-margin auto" as "rmse_margin='auto'",
// "--no-plots" as "plots=False", any other "--some-option" as "some_option";
// one line of at most kMaxMessageLength characters.
inline constexpr std::size_t kMaxMessageLength = 300;
std::string python_message(const std::string& message);

// Translates the library's exceptions: fss::Error to ValueError (usage) or
// RuntimeError, OutOfMemory and failed allocations to MemoryError; messages
// through python_message.
void register_errors();

// Creates fss.FssimWarning (a UserWarning) as the attribute FssimWarning of `m`.
void register_warnings(py::module_& m);

// warnings.warn(message, fss.FssimWarning, stacklevel=2): the caller of the
// public function (fss/__init__.py wraps each compiled one). A filter that
// turns it into an exception: py::error_already_set.
void warn(const std::string& message);

}  // namespace fss::python
