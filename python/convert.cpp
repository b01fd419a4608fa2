// Python objects as C++ values, and the module's errors (convert.h).
#include "convert.h"

#include <pybind11/pybind11.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iterator>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
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

namespace {

// numpy's dtype.kind of a numpy scalar or array ('b', 'i', 'u', 'f', 'c', ...),
// '\0' for another object.
char numpy_kind(py::handle value) {
  if (!py::hasattr(value, "dtype")) return '\0';
  const py::object dtype = py::getattr(value, "dtype");
  if (!py::hasattr(dtype, "kind")) return '\0';
  return dtype.attr("kind").cast<std::string>().front();
}

// True for an array of one or more dimensions (never a number, even of size 1).
bool is_shaped_array(py::handle value) {
  return py::isinstance<py::array>(value) && py::reinterpret_borrow<py::array>(value).ndim() > 0;
}

bool is_bool(py::handle value) {
  return PyBool_Check(value.ptr()) != 0 || numpy_kind(value) == 'b';
}

}  // namespace

// A real number: float, int, numpy's real scalars and 0-d arrays, anything
// float() takes (Fraction, Decimal) but bool, complex numbers and text.
double float_argument(py::handle value, const char* argument) {
  const char kind = numpy_kind(value);
  const bool numpy_refused = kind != '\0' && kind != 'i' && kind != 'u' && kind != 'f';
  if (numpy_refused || is_bool(value) || is_shaped_array(value) ||
      PyComplex_Check(value.ptr()) != 0 || PyUnicode_Check(value.ptr()) != 0 ||
      PyBytes_Check(value.ptr()) != 0) {
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

// An integer as a Python int: what operator.index takes (int, numpy integers,
// 0-d integer arrays), or a real number that is an integer (3.0, numpy.float32(3));
// "seed = 3.5: must be an integer" for another number; bool is a TypeError.
py::int_ python_int(py::handle value, const char* argument) {
  if (is_bool(value) || is_shaped_array(value)) throw_type_error(argument, "an integer", value);
  PyObject* index = PyNumber_Index(value.ptr());
  if (index != nullptr) return py::reinterpret_steal<py::int_>(index);
  if (PyErr_ExceptionMatches(PyExc_TypeError) == 0) throw py::error_already_set();
  PyErr_Clear();
  double number = 0.0;
  try {
    number = float_argument(value, argument);
  } catch (const py::type_error&) {
    throw_type_error(argument, "an integer", value);
  }
  if (!std::isfinite(number) || number != std::trunc(number)) {
    throw py::value_error(std::string(argument) + " = " + fss::format_exact(number) +
                          ": must be an integer");
  }
  return py::reinterpret_steal<py::int_>(PyLong_FromDouble(number));
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

// ---------------------------------------------------------------------------
// Images

// data_range= (docs/python.md): given, a finite number > 0; None, 255 for
// uint8 and 65535 for uint16 (so v x 255 / 65535 = v / 257, as fssim reads a
// 16-bit PNG); no default for another dtype, whose scale is the user's to state.
double data_range_argument(py::handle data_range, const py::array& array, const char* argument) {
  if (data_range.is_none()) {
    const char kind = array.dtype().kind();
    const py::ssize_t size = array.dtype().itemsize();
    if (kind == 'u' && size == 1) return 255.0;
    if (kind == 'u' && size == 2) return 65535.0;
    throw py::value_error(
        std::string(argument) + ": dtype " +
        fss::shorten_for_message(py::str(array.dtype()).cast<std::string>()) +
        " needs data_range= (255 for gray levels 0..255, 1 for floats on [0, 1])");
  }
  const double value = float_argument(data_range, "data_range");
  if (!(std::isfinite(value) && value > 0.0)) {
    throw py::value_error("data_range = " + fss::format_exact(value) +
                          ": must be a finite number > 0 (the value of gray level 255)");
  }
  return value;
}

ImageArgument image_array_argument(py::handle value, py::handle data_range, const char* argument) {
  ImageArgument image;
  image.array = array_argument(value, argument, "an array, H x W or H x W x 3");
  const args::ArrayView view = view_of(image.array);
  args::check_real_dtype(view, argument);
  image.size = args::image_size(view.shape, argument);
  image.data_range = data_range_argument(data_range, image.array, argument);
  return image;
}

fss::Image image_from_argument(const ImageArgument& image, const char* argument) {
  return args::image_from_view(view_of(readable(image.array)), image.data_range, argument);
}

fss::Image image_argument(py::handle value, py::handle data_range, const char* argument) {
  return image_from_argument(image_array_argument(value, data_range, argument), argument);
}

// ---------------------------------------------------------------------------
// Outputs

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

py::array_t<double> array_from_image(fss::Image&& image) {
  if (image.channels != 1) return array_from_image(static_cast<const fss::Image&>(image));
  // The array owns the vector through a capsule that deletes it with the array.
  auto* values = new fss::Samples(std::move(image.data));
  const py::capsule owner(values, [](void* p) { delete static_cast<fss::Samples*>(p); });
  return py::array_t<double>(
      {static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width)},
      values->data(), owner);
}

py::array_t<double> array_from_vector(const std::vector<double>& values) {
  py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

py::float_ float_object(double value) { return py::float_(value); }

py::object optional_float_object(const std::optional<double>& value) {
  return value ? py::object(float_object(*value)) : py::object(py::none());
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

// ---------------------------------------------------------------------------
// Errors and warnings

namespace {

// The CLI's phrases that say more than an option's name, as Python keywords.
constexpr std::pair<std::string_view, std::string_view> kCliPhrases[] = {
    {"--mode numerical", "mode='numerical'"},
    {"--mode analog", "mode='analog'"},
    {"--rmse-margin auto", "rmse_margin='auto'"},
    {"--no-plots", "plots=False"},
};

// The options of fssim the library's messages name; each is the keyword of
// the same name, '-' as '_'.
constexpr std::string_view kCliOptions[] = {
    "adc-bits",
    "adc-gain",
    "code",
    "dark-current",
    "dt",
    "full-well",
    "input",
    "max-memory",
    "mode",
    "noise",
    "outdir",
    "png-depth",
    "prior",
    "read-noise",
    "regularization",
    "report",
    "restoration",
    "restore-velocity",
    "rmse-margin",
    "save-float",
    "sheet",
    "snr",
    "trials",
    "velocity",
    "velocity-distribution",
};

bool is_option_character(char c) {
  return std::islower(static_cast<unsigned char>(c)) != 0 ||
         std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '-';
}

// At `rest` (which begins with "--"), the Python words of a phrase or an option of fssim and
// the length they replace; nothing for any other text (a file named "--x.png").
std::optional<std::pair<std::string, std::size_t>> python_option(std::string_view rest) {
  for (const auto& [cli, python] : kCliPhrases) {
    if (rest.starts_with(cli) &&
        (rest.size() == cli.size() || !is_option_character(rest[cli.size()]))) {
      return std::pair{std::string(python), cli.size()};
    }
  }
  std::size_t end = 2;
  while (end < rest.size() && is_option_character(rest[end])) ++end;
  const std::string_view name = rest.substr(2, end - 2);
  if (std::find(std::begin(kCliOptions), std::end(kCliOptions), name) == std::end(kCliOptions)) {
    return std::nullopt;
  }
  std::string keyword(name);
  std::replace(keyword.begin(), keyword.end(), '-', '_');
  return std::pair{keyword, end};
}

// True when message[i] has a letter or digit on both sides (the apostrophe of "code's").
bool within_word(const std::string& message, std::size_t i) {
  const auto alnum = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; };
  return i > 0 && i + 1 < message.size() && alnum(message[i - 1]) && alnum(message[i + 1]);
}

// The message with fssim's options ("--rmse-margin", "--mode numerical") as Python keywords
// ("rmse_margin", "mode='numerical'"), outside the quoted names ('...') it holds.
std::string python_words(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  bool quoted = false;
  for (std::size_t i = 0; i < message.size();) {
    const std::string_view rest = std::string_view(message).substr(i);
    const bool starts_word =
        i == 0 || std::string_view(" (\"[,").find(message[i - 1]) != std::string_view::npos;
    if (!quoted && starts_word && rest.starts_with("--")) {
      if (const auto option = python_option(rest)) {
        out += option->first;
        i += option->second;
        continue;
      }
    }
    if (message[i] == '\'' && !within_word(message, i)) quoted = !quoted;
    out += message[i++];
  }
  return out;
}

// A Python str of UTF-8 `text`, bytes that are not UTF-8 as \xNN.
py::str decoded(const std::string& text) {
  PyObject* object =
      PyUnicode_DecodeUTF8(text.data(), static_cast<Py_ssize_t>(text.size()), "backslashreplace");
  if (object == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(object);
}

// Sets a Python exception of `type` with python_message(message).
void set_error(PyObject* type, const char* message) {
  try {
    PyErr_SetObject(type, decoded(python_message(message)).ptr());
  } catch (py::error_already_set& e) {
    e.restore();  // the decoding's own error
  }
}

PyObject* warning_category = nullptr;  // fss.FssimWarning, created once

}  // namespace

// One line (control bytes as \xNN), in Python words, cut after
// kMaxMessageLength characters with "..." (never inside a UTF-8 sequence).
std::string python_message(const std::string& message) {
  std::string text = python_words(fss::escape_control_characters(message));
  if (text.size() <= kMaxMessageLength) return text;
  std::size_t end = kMaxMessageLength - 3;
  for (int back = 0; back < 3 && (static_cast<unsigned char>(text[end]) & 0xC0U) == 0x80U; ++back) {
    --end;
  }
  text.resize(end);
  return text + "...";
}

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

void register_warnings(py::module_& m) {
  if (warning_category == nullptr) {
    warning_category = PyErr_NewExceptionWithDoc(
        "fss.FssimWarning",
        "A warning of fssim (the text fssim prints after \"fssim: warning: \"): the run "
        "went through but a result may not mean what it usually does.",
        PyExc_UserWarning, nullptr);
    if (warning_category == nullptr) throw py::error_already_set();
  }
  m.attr("FssimWarning") = py::handle(warning_category);
}

// Stack level 2: the caller of the public function, which fss/__init__.py
// wraps in a Python function.
void warn(const std::string& message) {
  if (warning_category == nullptr) throw std::logic_error("fss.FssimWarning is not registered");
  const py::str text = decoded(python_words(fss::escape_control_characters(message)));
  const char* utf8 = PyUnicode_AsUTF8(text.ptr());
  if (utf8 == nullptr || PyErr_WarnEx(warning_category, utf8, 2) != 0) {
    throw py::error_already_set();
  }
}

}  // namespace fss::python
