// libFuzzer target: the Python module's argument checks and conversions
// (python/arguments.h), which the module's glue feeds with the numbers,
// strings and array memory of a call. The first byte chooses the function:
//   0 simulation_options, then the memory estimate of a run of a fuzzed size
//   1 image_from_view (its data_range first)   2 values_from_view
//   3 code_from_view, transfer_values
//   4 generate_options  5 optimize_options   6 the text arguments
// The bytes after it are the values, read front to back (a number: one byte
// choosing a notable value or the raw bits of the next 8; past the end every
// value is 0); an array takes its dtype, shape and strides from them and its
// memory from what is left, in place (unaligned, as numpy allows).
// A usage fss::Error of one short line is the expected end of bad values (a
// limit one for the memory check); any other exception, a crash, a sanitizer
// report, a long or multi-line message, options the library's IsValid
// refuses, or a value that is not finite in what is returned is a bug.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "arguments.h"
#include "fuzz_check.h"

namespace {

namespace args = fss::python;

class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  template <typename T>
  T take() {
    T value{};
    const std::size_t n = std::min(sizeof value, size_ - used_);
    std::memcpy(&value, data_ + used_, n);
    used_ += n;
    return value;
  }
  std::uint8_t byte() { return take<std::uint8_t>(); }
  double number() {
    static constexpr double kNotable[] = {
        0.0,    -0.0,  1.0,   -1.0,   2.0, 0.5,      1e-100,    1e100,
        1e-101, 1e101, 1e308, 5e-324, NAN, INFINITY, -INFINITY, 1.9999999999999998};
    const std::uint8_t choice = byte();
    if (choice < std::size(kNotable)) return kNotable[choice];
    return take<double>();
  }
  long long integer() {
    const std::uint8_t choice = byte();
    if (choice < 128) return static_cast<long long>(choice) - 8;  // small values, some negative
    return take<long long>();
  }
  std::string text() {
    const std::size_t length = std::min<std::size_t>(byte() % 24, size_ - used_);
    std::string value(reinterpret_cast<const char*>(data_ + used_), length);
    used_ += length;
    return value;
  }
  // The bytes not read yet.
  const std::uint8_t* rest() const { return data_ + used_; }
  std::size_t rest_size() const { return size_ - used_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t used_ = 0;
};

// An array of a fuzzed dtype, shape and strides over the input's remaining
// bytes; false when those bytes cannot hold it.
bool make_view(Input& in, args::ArrayView& view) {
  static constexpr char kKinds[] = {'b', 'i', 'u', 'f', 'c', 'O'};
  static constexpr std::size_t kSizes[] = {1, 2, 4, 8, 16};
  view.kind = kKinds[in.byte() % std::size(kKinds)];
  view.itemsize = kSizes[in.byte() % std::size(kSizes)];
  view.native = in.byte() % 8 != 0;
  view.dtype = std::string(1, view.kind) + std::to_string(view.itemsize);
  const int dimensions = in.byte() % 5;
  std::int64_t low = 0;
  std::int64_t high = 0;
  bool empty = false;
  for (int d = 0; d < dimensions; ++d) {
    const std::int64_t side = in.byte() % 9;
    const std::int64_t stride = static_cast<std::int64_t>(in.byte()) - 128;  // bytes, any sign
    view.shape.push_back(side);
    view.strides.push_back(stride);
    empty = empty || side == 0;
    const std::int64_t reach = (side > 0 ? side - 1 : 0) * stride;
    (reach < 0 ? low : high) += reach;
  }
  const auto needed = static_cast<std::size_t>(high - low) + view.itemsize;
  if (!empty && needed > in.rest_size()) return false;
  view.data = in.rest() + (empty ? 0 : -low);
  return true;
}

std::size_t element_count(const args::ArrayView& view) {
  std::size_t count = 1;
  for (const std::int64_t side : view.shape) count *= static_cast<std::size_t>(side);
  return count;
}

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void fuzz_simulation_options(Input& in) {
  args::SimulateArguments a;
  a.mode = in.byte() % 4 == 0 ? in.text() : (in.byte() % 2 == 0 ? "numerical" : "analog");
  a.noise = in.byte() % 4 == 0 ? in.text() : (in.byte() % 2 == 0 ? "poisson" : "aggregated");
  a.velocity = in.number();
  a.snr = in.number();
  a.dt = in.number();
  a.seed = in.take<std::uint64_t>();
  a.trials = in.integer();
  if (in.byte() % 2 == 0) a.restore_velocity = in.number();
  a.threads = in.integer();
  if (in.byte() % 2 == 0) a.rmse_margin = in.integer();
  a.max_memory = in.take<std::uint64_t>();
  a.read_noise = in.number();
  a.dark_current = in.number();
  if (in.byte() % 2 == 0) a.full_well = in.number();
  a.adc_bits = in.integer();
  if (in.byte() % 2 == 0) a.adc_gain = in.number();
  const fss::SimulationOptions options = args::simulation_options(a);
  require(options.IsValid(nullptr));
  require(!a.adc_gain || options.sensor.adc_bits != 0);
  // The memory check of an image of a fuzzed size with a fuzzed code.
  const args::ImageSize size{static_cast<int>(in.take<std::uint16_t>()) + 1,
                             static_cast<int>(in.take<std::uint16_t>()) + 1,
                             in.byte() % 2 == 0 ? 1 : 3};
  fss::ShutterCode code{"fuzz", std::vector<double>(in.byte() % 64)};
  for (double& gain : code.gains) gain = in.number();
  args::check_simulation_memory(options, code, size);
  require(options.max_memory_bytes == 0 ||
          args::simulation_memory_bytes(options, code, size) <= options.max_memory_bytes);
}

void fuzz_arrays(Input& in, int choice) {
  // data_range as the module passes it: a finite number > 0 (convert.cpp refuses others).
  double data_range = 255.0;
  if (choice == 1) {
    const double number = in.number();
    if (std::isfinite(number) && number > 0.0) data_range = number;
  }
  args::ArrayView view;
  if (!make_view(in, view)) return;
  if (choice == 1) {
    const fss::Image image = args::image_from_view(view, data_range);
    require(image.height == view.shape[0] && image.width == view.shape[1]);
    for (const double value : image.data) require(std::isfinite(value));
  } else if (choice == 2) {
    const std::vector<double> values = args::values_from_view(view, "xi");
    require(values.size() == element_count(view));
    for (const double value : values) require(std::isfinite(value));
  } else {
    const fss::ShutterCode code = args::code_from_view(view);
    require(code.gains.size() <= static_cast<std::size_t>(fss::kMaxCodeLength));
    std::vector<double> xi(in.byte() % 8);
    for (double& value : xi) value = in.number();
    const double velocity = in.number();
    const double dt = in.number();
    std::vector<std::complex<double>> values(xi.size());
    args::transfer_values(code, xi, velocity, dt, values);
    for (const auto& value : values) require(std::isfinite(std::abs(value)));
  }
}

void fuzz_design(Input& in, int choice) {
  if (choice == 4) {
    const std::string family = in.text();
    const long long length = in.integer();
    const double velocity = in.number();
    const double dt = in.number();
    const fss::GenerateOptions options = args::generate_options(
        family, length, velocity, dt, in.take<std::uint64_t>(), in.byte() & 1);
    require(options.IsValid(nullptr));
    return;
  }
  args::OptimizeArguments a;
  a.length = in.integer();
  a.velocity = in.number();
  a.dt = in.number();
  a.snr = in.number();
  a.mode = in.byte() % 4 == 0 ? in.text() : "analog";
  a.binary = (in.byte() & 1) != 0;
  a.min_light = in.number();
  a.restarts = in.integer();
  a.iterations = in.integer();
  a.seed = in.take<std::uint64_t>();
  a.grid_points = in.integer();
  require(args::optimize_options(a).IsValid(nullptr));
}

void fuzz_texts(Input& in) {
  const std::string text = in.text();
  static constexpr std::pair<std::string_view, std::string_view> kNames[] = {
      {"velocity_px_per_slot", "velocity"}, {"sensor.adc_bits", "adc_bits"}};
  const std::string renamed = args::rename_field(text, kNames);
  require(renamed.size() <= text.size());
  bool refused = false;
  try {
    args::check_no_nul("path", text);
  } catch (const fss::Error& e) {
    fss::fuzz::check_message(e, 400);
    refused = true;
  }
  require(refused == (text.find('\0') != std::string::npos));
  args::mode_argument(text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Input in(data, size);
  const int choice = in.byte() % 7;
  try {
    if (choice == 0) fuzz_simulation_options(in);
    if (choice >= 1 && choice <= 3) fuzz_arrays(in, choice);
    if (choice == 4 || choice == 5) fuzz_design(in, choice);
    if (choice == 6) fuzz_texts(in);
  } catch (const fss::Error& e) {
    if (e.kind() != fss::ErrorKind::kLimit) {
      fss::fuzz::check_message(e, 400);
    } else {
      require(choice == 0 && std::strchr(e.what(), '\n') == nullptr);
    }
  }
  return 0;
}
