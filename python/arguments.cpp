#include "arguments.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "fss/core/error.h"
#include "fss/design/analyze.h"
#include "fss/io/png_io.h"
#include "fss/model/transfer.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/memory_estimate.h"
#include "fss/pipeline/option_rules.h"
#include "pipeline/run_checks.h"

namespace fss::python {

namespace {

using Names = std::pair<std::string_view, std::string_view>;

// A user's text in a message: control bytes as \xNN, at most 40 characters.
std::string quote_text(std::string_view text) {
  std::string quoted_text(1, '\'');
  quoted_text += shorten_for_message(text);
  quoted_text += '\'';
  return quoted_text;
}

[[noreturn]] void throw_rule(std::string_view argument, const std::string& value,
                             const std::string& rule) {
  throw_usage_error(std::string(argument) + " = " + value + ": " + rule);
}

}  // namespace

void refuse_velocity_with_distribution(bool velocity_given, double velocity) {
  if (!velocity_given) return;
  throw_usage_error("velocity_distribution: refused with velocity = " + format_exact(velocity) +
                    " (a velocity or a distribution of velocities, not both; give one)");
}

std::string rename_field(const std::string& message, FieldNames names) {
  const std::string_view text(message);
  for (const auto& [field, argument] : names) {
    if (text.size() > field.size() && text.substr(0, field.size()) == field &&
        text[field.size()] == ' ') {
      return std::string(argument) + message.substr(field.size());
    }
  }
  return message;
}

void check_no_nul(std::string_view argument, std::string_view text) {
  if (text.find('\0') != std::string_view::npos) {
    throw_usage_error(std::string(argument) + ": " + quote_text(text) +
                      " contains a NUL byte (not allowed in a path or a name)");
  }
}

int int_argument(std::string_view argument, long long value, long long minimum, long long maximum) {
  if (value < INT_MIN || value > INT_MAX) {
    throw_rule(
        argument, std::to_string(value),
        "must be an integer in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]");
  }
  return static_cast<int>(value);
}

void check_velocity(std::string_view argument, double value) {
  if (const std::string rule = velocity_rule(value); !rule.empty()) {
    throw_rule(argument, format_exact(value), rule);
  }
}

void check_scale(std::string_view argument, double value) {
  if (const std::string rule = scale_rule(value); !rule.empty()) {
    throw_rule(argument, format_exact(value), rule);
  }
}

fss::ShutterMode mode_argument(std::string_view text) {
  const std::optional<ShutterMode> mode = shutter_mode_from_string(text);
  if (!mode) throw_usage_error("mode: " + quote_text(text) + " is not 'numerical' or 'analog'");
  return *mode;
}

// ---------------------------------------------------------------------------
// fss.simulate

namespace {

constexpr std::array<Names, 12> kSimulateNames = {{
    {"restoration.regularization", "regularization"},
    {"restoration.prior_exponent", "prior"},
    {"restoration.prior_level", "prior"},
    {"restoration.prior", "prior"},
    {"velocity_px_per_slot", "velocity"},
    {"restore_velocity_px_per_slot", "restore_velocity"},
    {"rmse_margin_columns", "rmse_margin"},
    {"sensor.read_noise_electrons", "read_noise"},
    {"sensor.dark_current_electrons_per_slot", "dark_current"},
    {"sensor.full_well_electrons", "full_well"},
    {"sensor.adc_bits", "adc_bits"},
    {"sensor.adc_gain_electrons_per_count", "adc_gain"},
}};

NoiseModel noise_argument(std::string_view text) {
  const std::optional<NoiseModel> noise = noise_model_from_string(text);
  if (!noise) {
    throw_usage_error("noise: " + quote_text(text) + " is not 'poisson', 'aggregated' or 'none'");
  }
  return *noise;
}

// restoration, regularization and prior into `options`.
void restoration_arguments(const SimulateArguments& a, SimulationOptions& options) {
  const std::optional<RestorationMethod> method = restoration_method_from_string(a.restoration);
  if (!method) {
    throw_usage_error("restoration: " + quote_text(a.restoration) +
                      " is not 'inverse', 'tikhonov' or 'wiener'");
  }
  RestorationOptions& r = options.restoration;
  r.method = *method;
  if ((a.regularization || a.regularization_optimal) && r.method != RestorationMethod::kTikhonov) {
    throw_usage_error("regularization: only restoration='tikhonov' takes it (this run is " +
                      a.restoration + ")");
  }
  r.regularization = a.regularization;
  if (a.prior && r.method != RestorationMethod::kWiener) {
    throw_usage_error("prior: only restoration='wiener' takes it (this run is " + a.restoration +
                      ")");
  }
  std::string problem;
  if (a.prior && !parse_prior(*a.prior, &r, &problem)) throw_usage_error("prior: " + problem);
  if (r.prior_level) {
    throw_usage_error("prior: " + quote_text(*a.prior) +
                      " gives a level; a simulation estimates it from a calibration observation "
                      "(give 'power-law' or 'power-law:GAMMA')");
  }
}

}  // namespace

SimulationOptions simulation_options(const SimulateArguments& a) {
  SimulationOptions options;
  options.mode = mode_argument(a.mode);
  options.noise = noise_argument(a.noise);
  options.velocity_px_per_slot = a.velocity;
  if (a.velocity_distribution) {
    refuse_velocity_with_distribution(a.velocity_given, a.velocity);
    options.velocity_distribution =
        load_velocity_distribution(*a.velocity_distribution, "velocity_distribution");
  }
  options.restore_velocity_px_per_slot = a.restore_velocity;
  options.snr = a.snr;
  options.dt = a.dt;
  options.seed = a.seed;
  options.trials = int_argument("trials", a.trials, 1, INT_MAX);
  options.threads = int_argument("threads", a.threads, 0, INT_MAX);
  if (a.rmse_margin_auto) {
    options.rmse_margin_columns = kRmseMarginAuto;
  } else if (!a.rmse_margin) {
    options.rmse_margin_columns = kRmseMarginDefault;
  } else if (*a.rmse_margin < 0) {
    throw_rule("rmse_margin", std::to_string(*a.rmse_margin),
               "must be >= 0 (or None for 3B, or 'auto')");
  } else {
    options.rmse_margin_columns = int_argument("rmse_margin", *a.rmse_margin, 0, kMaxMarginColumns);
  }
  options.max_memory_bytes = static_cast<std::size_t>(a.max_memory);
  options.sensor.read_noise_electrons = a.read_noise;
  options.sensor.dark_current_electrons_per_slot = a.dark_current;
  options.sensor.full_well_electrons = a.full_well;
  options.sensor.adc_bits = int_argument("adc_bits", a.adc_bits, 0, 32);
  options.sensor.adc_gain_electrons_per_count = a.adc_gain.value_or(1.0);
  restoration_arguments(a, options);
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(rename_field(error, kSimulateNames));
  if (a.adc_gain && options.sensor.adc_bits == 0) {
    throw_usage_error("adc_gain: needs adc_bits (without an ADC there are no counts)");
  }
  return options;
}

// ---------------------------------------------------------------------------
// Arrays

namespace {

// Calls visit(T{}) with T the C++ type of a readable dtype; false when the
// dtype is not readable. bool stands for numpy's bool (a byte, 0 or not).
template <typename Visit>
bool visit_dtype(const ArrayView& view, Visit&& visit) {
  if (!view.native) return false;
  const std::size_t size = view.itemsize;
  switch (view.kind) {
    case 'b':
      if (size == 1) return visit(bool{}), true;
      return false;
    case 'i':
      if (size == 1) return visit(std::int8_t{}), true;
      if (size == 2) return visit(std::int16_t{}), true;
      if (size == 4) return visit(std::int32_t{}), true;
      if (size == 8) return visit(std::int64_t{}), true;
      return false;
    case 'u':
      if (size == 1) return visit(std::uint8_t{}), true;
      if (size == 2) return visit(std::uint16_t{}), true;
      if (size == 4) return visit(std::uint32_t{}), true;
      if (size == 8) return visit(std::uint64_t{}), true;
      return false;
    case 'f':
      if (size == 4) return visit(float{}), true;
      if (size == 8) return visit(double{}), true;
      return false;
    default:
      return false;
  }
}

// The element at `p` as a double (memcpy: numpy allows unaligned arrays).
template <typename T>
double read_value(const unsigned char* p) {
  if constexpr (std::is_same_v<T, bool>) {
    return *p != 0 ? 1.0 : 0.0;
  } else {
    T value;
    std::memcpy(&value, p, sizeof value);
    return static_cast<double>(value);
  }
}

[[noreturn]] void throw_unreadable(const ArrayView& view, std::string_view argument) {
  throw_usage_error(std::string(argument) + ": dtype " + shorten_for_message(view.dtype) +
                    " is not read directly (expected bool, (u)int8 to (u)int64, float32 or "
                    "float64 in native byte order)");
}

// "(0, 3)" for a multi-dimensional index, "3" for a one-dimensional one.
std::string index_text(const std::vector<std::int64_t>& index) {
  if (index.size() == 1) return std::to_string(index[0]);
  return shape_text(index);
}

// The refusal of the value at row y, column x: not finite, or (`scaled`) its
// gray level value x 255 / data_range is not.
[[noreturn]] void throw_not_finite(std::string_view argument, double value, int y, int x,
                                   bool scaled, double data_range) {
  throw_usage_error(std::string(argument) + ": value " + format_number(value) + " at row " +
                    std::to_string(y) + ", column " + std::to_string(x) +
                    (scaled ? " has no finite gray level (value x 255 / data_range, data_range = " +
                                  format_exact(data_range) + ")"
                            : " is not finite"));
}

// Gray level = value x 255 / data_range, the value itself for a data_range of
// 255 (docs/python.md): (v 255) / 65535 is v / 257 to the bit for a 16-bit v,
// as fssim reads a 16-bit PNG, both being the correctly rounded v / 257.
template <typename T>
void fill_image(const ArrayView& view, double data_range, std::string_view argument, Image& image) {
  const auto* base = static_cast<const unsigned char*>(view.data);
  const std::int64_t row_stride = view.strides[0];
  const std::int64_t column_stride = view.strides[1];
  const std::int64_t channel_stride = view.strides.size() == 3 ? view.strides[2] : 0;
  const bool scaled = data_range != 255.0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* pixel = base + y * row_stride + x * column_stride;
      for (int c = 0; c < image.channels; ++c) {
        const double value = read_value<T>(pixel + c * channel_stride);
        if constexpr (std::is_floating_point_v<T>) {
          if (!std::isfinite(value)) throw_not_finite(argument, value, y, x, false, data_range);
        }
        const double gray = scaled ? value * 255.0 / data_range : value;
        if (scaled && !std::isfinite(gray)) {
          throw_not_finite(argument, value, y, x, true, data_range);
        }
        image.at(c, y, x) = gray;
      }
    }
  }
}

// `noun` names a value in a message: "value", "gain".
template <typename T>
void fill_values(const ArrayView& view, std::string_view argument, std::string_view noun,
                 std::vector<double>& values) {
  const auto* base = static_cast<const unsigned char*>(view.data);
  const std::size_t dimensions = view.shape.size();
  std::vector<std::int64_t> index(dimensions, 0);
  std::int64_t offset = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double value = read_value<T>(base + offset);
    if (!std::isfinite(value)) {
      throw_usage_error(
          std::string(argument) + ": " + std::string(noun) + " " + format_number(value) +
          (dimensions == 0 ? std::string() : " at index " + index_text(index)) + " is not finite");
    }
    values[i] = value;
    // The next index in C order: the last dimension first.
    for (std::size_t d = dimensions; d-- > 0;) {
      offset += view.strides[d];
      if (++index[d] < view.shape[d]) break;
      offset -= view.strides[d] * view.shape[d];
      index[d] = 0;
    }
  }
}

}  // namespace

void check_real_dtype(const ArrayView& view, std::string_view argument) {
  const char kind = view.kind;
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f') {
    // Text given as an image is most likely a file name.
    const bool text = kind == 'U' || kind == 'S';
    const std::string hint =
        text && argument == "image" ? "; for a file, fss.read_image(path)" : "";
    throw_usage_error(std::string(argument) + ": dtype " + shorten_for_message(view.dtype) +
                      " is not a real numeric type (expected bool, integer or float" + hint + ")");
  }
}

bool is_readable(const ArrayView& view) {
  return visit_dtype(view, [](auto) {});
}

std::string shape_text(std::span<const std::int64_t> shape) {
  std::string text = "(";
  for (std::size_t d = 0; d < shape.size(); ++d) {
    text += (d > 0 ? ", " : "") + std::to_string(shape[d]);
  }
  return text + (shape.size() == 1 ? ",)" : ")");
}

ImageSize image_size(std::span<const std::int64_t> shape, std::string_view argument) {
  const bool layout_ok =
      shape.size() == 2 || (shape.size() == 3 && (shape[2] == 1 || shape[2] == 3));
  if (!layout_ok) {
    throw_usage_error(std::string(argument) + ": shape " + shape_text(shape) +
                      " is not H x W (gray) or H x W x 3 (RGB)");
  }
  if (shape[0] < 1 || shape[1] < 1 || shape[0] > kMaxImageSide || shape[1] > kMaxImageSide) {
    throw_usage_error(std::string(argument) + ": shape " + shape_text(shape) + " must have 1 to " +
                      std::to_string(kMaxImageSide) + " rows and columns");
  }
  return {static_cast<int>(shape[1]), static_cast<int>(shape[0]),
          shape.size() == 3 ? static_cast<int>(shape[2]) : 1};
}

Image image_from_view(const ArrayView& view, double data_range, std::string_view argument) {
  check_real_dtype(view, argument);
  const ImageSize size = image_size(view.shape, argument);
  Image image(size.width, size.height, size.channels);
  const bool read = visit_dtype(
      view, [&](auto type) { fill_image<decltype(type)>(view, data_range, argument, image); });
  if (!read) throw_unreadable(view, argument);
  return image;
}

std::vector<double> values_from_view(const ArrayView& view, std::string_view argument) {
  check_real_dtype(view, argument);
  std::size_t count = 1;
  for (const std::int64_t side : view.shape) count *= static_cast<std::size_t>(side);
  std::vector<double> values(count);
  const bool read = visit_dtype(
      view, [&](auto type) { fill_values<decltype(type)>(view, argument, "value", values); });
  if (!read) throw_unreadable(view, argument);
  return values;
}

ShutterCode code_from_view(const ArrayView& view) {
  check_real_dtype(view, "code");
  if (view.shape.size() != 1) {
    throw_usage_error("code: gains of shape " + shape_text(view.shape) +
                      " are not one-dimensional");
  }
  if (view.shape[0] > kMaxCodeLength) {
    throw_usage_error("code: " + std::to_string(view.shape[0]) + " gains, more than " +
                      std::to_string(kMaxCodeLength) + " (the longest code fssim analyses)");
  }
  ShutterCode code{"array", {}};
  const std::string_view argument = "code";
  code.gains.resize(static_cast<std::size_t>(view.shape[0]));
  const bool read = visit_dtype(
      view, [&](auto type) { fill_values<decltype(type)>(view, argument, "gain", code.gains); });
  if (!read) throw_unreadable(view, argument);
  return code;
}

// ---------------------------------------------------------------------------
// Memory of fss.simulate

namespace {

// The module's outputs, per sample of the output crop: the ground truth crop
// (an Image) and the observed, restored and ground truth float64 arrays, 32
// bytes, where fssim's four PNG files take 4 (the estimate's own).
constexpr std::size_t kExtraOutputBytesPerSample = 32 - 4;

}  // namespace

std::size_t simulation_memory_bytes(const SimulationOptions& options, const ShutterCode& code,
                                    const ImageSize& size) {
  check_code_for_mode(code, options.mode);
  if (const std::string excess = restore_blur_excess(options, size.width, code.length());
      !excess.empty()) {
    throw_usage_error(
        "restore_velocity = " + format_exact(options.restore_velocity_px_per_slot.value_or(0.0)) +
        ": its blur " + excess);
  }
  return estimate_run_memory_bytes({size.width, size.height, size.channels}, options, code, false,
                                   kExtraOutputBytesPerSample);
}

void check_simulation_memory(const SimulationOptions& options, const ShutterCode& code,
                             const ImageSize& size) {
  const std::size_t needed = simulation_memory_bytes(options, code, size);  // usage errors first
  if (options.max_memory_bytes != 0 && needed > options.max_memory_bytes) {
    throw_memory_limit_error("a run on this " + std::to_string(size.width) + " x " +
                                 std::to_string(size.height) + " x " +
                                 std::to_string(size.channels) + " image",
                             needed, options.max_memory_bytes);
  }
}

// ---------------------------------------------------------------------------
// Codes

void transfer_values(const ShutterCode& code, std::span<const double> xi, double velocity,
                     double dt, std::span<std::complex<double>> values) {
  check_velocity("velocity", velocity);
  check_scale("dt", dt);
  check_code_for_mode(code, ShutterMode::kNumerical);
  for (std::size_t i = 0; i < xi.size(); ++i) {
    values[i] = transfer_function(code.gains, velocity, dt, xi[i]);
    if (!std::isfinite(values[i].real()) || !std::isfinite(values[i].imag())) {
      throw_usage_error("xi = " + format_exact(xi[i]) + ": K(xi) of code " + quote_text(code.name) +
                        " is not finite at velocity = " + format_exact(velocity) +
                        ", dt = " + format_exact(dt) + " (xi velocity dt is too large)");
    }
  }
}

void check_analysis_arguments(double velocity, double dt, double snr) {
  check_velocity("velocity", velocity);
  check_scale("dt", dt);
  check_scale("snr", snr);
}

VelocityDistribution design_distribution(const std::string& spec, bool velocity_given,
                                         double velocity) {
  refuse_velocity_with_distribution(velocity_given, velocity);
  return load_velocity_distribution(spec, "velocity_distribution");
}

GenerateOptions generate_options(std::string_view family, long long length, double velocity,
                                 double dt, std::uint64_t seed, bool analog) {
  GenerateOptions options;
  const std::optional<CodeFamily> parsed = code_family_from_string(family);
  if (!parsed) {
    throw_usage_error("family: " + quote_text(family) +
                      " is not one of sinc, mip, random, snapshot, accumulation");
  }
  options.family = *parsed;
  options.length = int_argument("length", length, 1, kMaxGeneratedCodeLength);
  check_velocity("velocity", velocity);
  check_scale("dt", dt);
  options.velocity_px_per_slot = velocity;
  options.dt = dt;
  options.seed = seed;
  options.analog = analog;
  static constexpr std::array<Names, 1> kNames = {{{"velocity_px_per_slot", "velocity"}}};
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(rename_field(error, kNames));
  return options;
}

OptimizeOptions optimize_options(const OptimizeArguments& a) {
  OptimizeOptions options;
  options.length = int_argument("length", a.length, 1, kMaxOptimizedCodeLength);
  if (a.velocity_distribution) {
    options.velocity_distribution =
        design_distribution(*a.velocity_distribution, a.velocity_given, a.velocity);
  } else if (!a.velocity_given) {
    throw_usage_error("velocity: give a velocity or a velocity_distribution");
  } else {
    check_velocity("velocity", a.velocity);
    options.velocity_px_per_slot = a.velocity;
  }
  check_scale("dt", a.dt);
  check_scale("snr", a.snr);
  options.dt = a.dt;
  options.snr = a.snr;
  options.mode = mode_argument(a.mode);
  options.binary = a.binary;
  options.min_light_slots = a.min_light;
  options.restarts = int_argument("restarts", a.restarts, 0, kMaxRestarts);
  options.max_iterations = int_argument("iterations", a.iterations, 1, kMaxIterations);
  options.seed = a.seed;
  options.grid_points = int_argument("grid_points", a.grid_points, 16, kMaxObjectiveGridPoints);
  static constexpr std::array<Names, 3> kNames = {{{"velocity_px_per_slot", "velocity"},
                                                   {"min_light_slots", "min_light"},
                                                   {"max_iterations", "iterations"}}};
  std::string error;
  if (!options.IsValid(&error)) throw_usage_error(rename_field(error, kNames));
  return options;
}

}  // namespace fss::python
