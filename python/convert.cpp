// Python objects as C++ values, and the module's errors (convert.h).
#include "convert.h"

#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "arguments.h"
#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/model/code.h"

namespace fss::python {

namespace args = fss::python;

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
std::uint64_t uint64_argument(py::handle value, const char* argument, const char* note) {
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

namespace {

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

}  // namespace

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

}  // namespace fss::python
