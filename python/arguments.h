// The arguments of the Python module `fss` as the library's options, codes and
// images, in plain C++. The module's glue (fss_module.cpp) turns each Python
// object into a number, a string or a view of an array's memory; these
// functions check and convert them without the interpreter, so that a fuzz
// target runs them too (tests/fuzz/fuzz_python_arguments.cpp).
//
// Every refusal is a usage fss::Error (ValueError in Python) of one line
// naming the Python argument, with the library's rules (option_rules.h,
// SimulationOptions::IsValid, SensorModel::IsValid, ...) in their words:
//   "velocity = nan: must be a finite number", "read_noise = -1: must be
//   finite and >= 0", "adc_gain: needs adc_bits (...)".
// A run over the memory limit is a limit fss::Error, as in Simulate.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fss/core/image.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss::python {

// Library field -> Python argument, for rename_field.
using FieldNames = std::span<const std::pair<std::string_view, std::string_view>>;

// `message` with its leading library field ("velocity_px_per_slot = 3 with
// ...", "sensor.adc_bits = 40: ...") named as the Python argument; a
// message that begins with no field of `names` is returned as it is.
std::string rename_field(const std::string& message, FieldNames names);

// The refusal of a velocity distribution given with a velocity ("velocity_distribution: refused
// with velocity = 1 (...)"); nothing when the velocity was not given.
void refuse_velocity_with_distribution(bool velocity_given, double velocity);

// A path or a code name: a usage error "<argument>: '<text>' contains a NUL
// byte (...)" when it holds one (the operating system would read the text
// before it as the whole name).
void check_no_nul(std::string_view argument, std::string_view text);

// An integer argument as an int. Within the range of int it is returned as it
// is (the library's rule checks it later); outside, a usage error
// "<argument> = <value>: must be an integer in [<minimum>, <maximum>]", the
// bounds fssim gives the option.
int int_argument(std::string_view argument, long long value, long long minimum, long long maximum);

// option_rules.h's velocity_rule and scale_rule for an argument:
// "<argument> = <value>: <rule>".
void check_velocity(std::string_view argument, double value);
void check_scale(std::string_view argument, double value);

fss::ShutterMode mode_argument(std::string_view text);  // "numerical" or "analog"

// ---------------------------------------------------------------------------
// fss.simulate

// The keywords of fss.simulate but the image and the code.
struct SimulateArguments {
  std::string mode = "numerical";
  double velocity = 1.0;
  bool velocity_given = true;  // false: velocity=None, the default 1
  // A distribution of velocities (docs/method.md §13): "uniform:LO:HI", "normal:MEAN:SD",
  // "normal:MEAN:SD:LO:HI" or the path of a file of "velocity weight" lines
  // (load_velocity_distribution); refused with a velocity given.
  std::optional<std::string> velocity_distribution;
  double snr = 100.0;
  double dt = 1.0;
  std::uint64_t seed = 0;
  long long trials = 1;
  std::string noise = "poisson";
  std::optional<double> restore_velocity;
  long long threads = 0;
  std::optional<long long> rmse_margin;  // empty: 3 B
  bool rmse_margin_auto = false;         // rmse_margin='auto'
  std::uint64_t max_memory = 0;          // bytes; 0: no limit
  double read_noise = 0.0;
  double dark_current = 0.0;
  std::optional<double> full_well;
  long long adc_bits = 0;
  std::optional<double> adc_gain;  // empty: not given (1 electron per count)
  // The restoration (docs/method.md §12): "inverse", "tikhonov" or "wiener"; the regularization
  // (Tikhonov) as a number, or "optimal", or not given; the prior (Wiener) as fssim's --prior.
  std::string restoration = "inverse";
  std::optional<double> regularization;
  bool regularization_optimal = false;  // regularization="optimal"
  std::optional<std::string> prior;
};

// The options of a run, checked as fssim checks its options
// (SimulationOptions::IsValid), named as the keywords; adc_gain without
// adc_bits is refused as fssim refuses --adc-gain without --adc-bits, and a
// regularization or a prior for a restoration that does not take it as fssim
// refuses them. A velocity distribution is read (a usage error naming "velocity_distribution"
// for a spec that does not parse or a file that does not exist, a runtime one for a file that
// cannot be read or parsed) and refused with a velocity given, as fssim refuses
// --velocity-distribution with --velocity.
fss::SimulationOptions simulation_options(const SimulateArguments& arguments);

// ---------------------------------------------------------------------------
// Arrays

// A numpy array's memory as the buffer protocol describes it: element
// [i0, i1, ...] at data + i0 strides[0] + i1 strides[1] + ... bytes.
struct ArrayView {
  const void* data = nullptr;
  std::vector<std::int64_t> shape;
  std::vector<std::int64_t> strides;  // in bytes, any sign
  char kind = 'f';  // numpy's dtype.kind: 'b' bool, 'i' signed, 'u' unsigned, 'f' float, ...
  std::size_t itemsize = 8;
  bool native = true;  // native byte order
  std::string dtype;   // numpy's name of the dtype, for messages ("complex128")
};

// A usage error "<argument>: dtype <dtype> is not a real numeric type
// (...)" unless the kind is bool, integer or float.
void check_real_dtype(const ArrayView& view, std::string_view argument);

// True when the functions below read the array as it is: bool, (u)int8 to
// (u)int64, float32, float64, in native byte order. Other real dtypes
// (float16, long double, swapped bytes) are converted to float64 first.
bool is_readable(const ArrayView& view);

// "(4,)", "(3, 5)": a shape as numpy writes it.
std::string shape_text(std::span<const std::int64_t> shape);

struct ImageSize {
  int width = 0;
  int height = 0;
  int channels = 0;
};

// H x W (gray) or H x W x C, C = 1 or 3, sides in [1, kMaxImageSide];
// otherwise a usage error naming `argument` and the shape.
ImageSize image_size(std::span<const std::int64_t> shape, std::string_view argument = "image");

// The array as a planar image, data[(c H + y) W + x] = array[y, x, c] on the
// gray-level scale: value x 255 / data_range (the value itself, bit for bit,
// for a data_range of 255). Usage errors naming `argument`: the shape
// (image_size), a dtype that is not readable, a value that is not finite
// ("image: value nan at row 3, column 5 is not finite") or whose gray level
// is not.
fss::Image image_from_view(const ArrayView& view, double data_range = 255.0,
                           std::string_view argument = "image");

// Every value of an array of any shape, in C order, checked finite
// ("xi: value nan at index (0, 3) is not finite"); a usage error for a dtype
// that is not readable.
std::vector<double> values_from_view(const ArrayView& view, std::string_view argument);

// A code given as gains: one dimension, at most kMaxCodeLength values, all
// finite; named "array".
fss::ShutterCode code_from_view(const ArrayView& view);

// ---------------------------------------------------------------------------
// Memory of fss.simulate

// Estimated peak memory of fss.simulate on an image of `size`:
// estimate_working_memory_bytes (Simulate's estimate, the image as doubles
// included) with the module's outputs in place of fssim's PNG files.
// Throws the usage error Simulate would for a code the mode cannot use or
// an image too narrow for the code (check_code_for_mode, Geometry::compute,
// metric_windows).
std::size_t simulation_memory_bytes(const fss::SimulationOptions& options,
                                    const fss::ShutterCode& code, const ImageSize& size);

// The limit fss::Error of Simulate when that estimate exceeds
// options.max_memory_bytes (not 0); made from the array's shape alone,
// before anything as large as the image is allocated.
void check_simulation_memory(const fss::SimulationOptions& options, const fss::ShutterCode& code,
                             const ImageSize& size);

// ---------------------------------------------------------------------------
// Codes

// fss.transfer_function: K(xi) for every xi into `values` (same size), after
// the checks of the code (check_code_for_mode, numerical), velocity and dt;
// a usage error "xi = <xi>: K(xi) of code '<name>' is not finite at ..."
// when a value leaves the range of doubles.
void transfer_values(const fss::ShutterCode& code, std::span<const double> xi, double velocity,
                     double dt, std::span<std::complex<double>> values);

// fss.analyze_code's setting, checked as `fssim code analyze` checks it.
void check_analysis_arguments(double velocity, double dt, double snr);

// A velocity distribution of the design functions (docs/method.md §13): read
// (load_velocity_distribution, named "velocity_distribution") and refused with a velocity given
// (`velocity_given`), as `fssim code analyze | optimize` refuses --velocity-distribution with
// --velocity; the design's rule on its support is the library's (analyze_code,
// OptimizeOptions::IsValid).
fss::VelocityDistribution design_distribution(const std::string& spec, bool velocity_given,
                                              double velocity);

// fss.generate_code's options, checked (GenerateOptions::IsValid) and named
// as its keywords.
fss::GenerateOptions generate_options(std::string_view family, long long length, double velocity,
                                      double dt, std::uint64_t seed, bool analog);

struct OptimizeArguments {
  long long length = 0;
  double velocity = 1.0;
  bool velocity_given = true;  // false: velocity=None (a distribution gives the velocities)
  std::optional<std::string> velocity_distribution;  // as SimulateArguments's
  double dt = 1.0;
  double snr = 100.0;
  std::string mode = "numerical";
  bool binary = false;
  double min_light = 0.0;
  long long restarts = 24;
  long long iterations = 300;
  std::uint64_t seed = 0;
  long long grid_points = 2048;
};

// fss.optimize_code's options, checked (OptimizeOptions::IsValid) and named
// as its keywords; a velocity or a velocity distribution, never both, nor neither.
fss::OptimizeOptions optimize_options(const OptimizeArguments& arguments);

}  // namespace fss::python
