#include "support/test_util.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <new>
#include <random>
#include <sstream>
#include <stdexcept>

namespace fss::test {

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "fssim-test-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  // Restore permissions a test may have removed, then delete.
  std::filesystem::permissions(path_, std::filesystem::perms::owner_all,
                               std::filesystem::perm_options::add, ec);
  std::filesystem::remove_all(path_, ec);
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot open " + path.string());
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!file) throw std::runtime_error("cannot write " + path.string());
}

std::vector<std::string> list_directory(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

CommandResult run_command(const std::string& command) {
  TempDir dir;
  const auto out_path = dir / "stdout";
  const auto err_path = dir / "stderr";
  const std::string full =
      command + " >'" + out_path.string() + "' 2>'" + err_path.string() + "' </dev/null";
  const int status = std::system(full.c_str());
  CommandResult result;
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  result.out = read_file(out_path);
  result.err = read_file(err_path);
  return result;
}

CommandResult run_fssim(const std::string& arguments) {
  return run_command(std::string("'") + FSSIM_BINARY_PATH + "' " + arguments);
}

Image make_test_image(int width, int height, int channels, std::uint64_t seed) {
  Image image(width, height, channels);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> texture(-20.0, 20.0);
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        double v = 40.0 + 150.0 * x / std::max(1, width - 1);  // ramp
        if ((x / 17 + y / 23 + c) % 2 == 0) v += 40.0;         // blocks with sharp edges
        v += 15.0 * std::sin(0.3 * y + 0.1 * c);               // smooth vertical variation
        v += texture(rng);                                     // texture
        image.at(c, y, x) = std::clamp(v, 0.0, 255.0);
      }
    }
  }
  return image;
}

void limit_address_space(std::size_t extra) {
  long pages = 0;  // the process's present size, /proc/self/statm's first field
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
    std::fclose(statm);
  }
  const rlim_t limit = static_cast<rlim_t>(pages) * ::sysconf(_SC_PAGESIZE) + extra;
  const rlimit value{limit, limit};
  if (pages == 0 || ::setrlimit(RLIMIT_AS, &value) != 0) std::_Exit(2);
}

std::string quote(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

namespace {

struct PngSink {
  std::vector<std::uint8_t> bytes;
  char message[200] = {0};
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof sink->message, "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

void on_png_write(png_structp png, png_bytep data, png_size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  bool out_of_memory = false;
  try {  // no exception may cross libpng's frames
    sink->bytes.insert(sink->bytes.end(), data, data + length);
  } catch (const std::bad_alloc&) {
    out_of_memory = true;
  }
  if (out_of_memory) png_error(png, "out of memory");
}

void on_png_flush(png_structp) {}

// The libpng calls. Nothing in this frame has a destructor, and png and info
// are not modified after setjmp, so reading them after a longjmp is defined.
bool run_png_writer(PngSink* sink, const PngSpec* spec, png_bytepp rows) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, on_png_error, on_png_warning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, on_png_write, on_png_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(spec->width),
               static_cast<png_uint_32>(spec->height), spec->bit_depth, spec->color_type,
               spec->interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!spec->palette.empty()) {
    png_set_PLTE(png, info, spec->palette.data(), static_cast<int>(spec->palette.size()));
  }
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::vector<std::uint8_t> craft_png(const PngSpec& spec) {
  PngSink sink;
  std::vector<std::vector<std::uint8_t>> rows = spec.rows;
  std::vector<png_bytep> pointers;
  for (std::vector<std::uint8_t>& row : rows) pointers.push_back(row.data());
  if (!run_png_writer(&sink, &spec, pointers.data())) {
    ADD_FAILURE() << "libpng could not write the test image: " << sink.message;
    return {};
  }
  return sink.bytes;
}

std::filesystem::path source_path(const std::string& relative) {
  return std::filesystem::path(FSS_SOURCE_DIR) / relative;
}

std::filesystem::path fixture_path(const std::string& relative) {
  return std::filesystem::path(FSS_FIXTURES_DIR) / relative;
}

std::vector<double> paper_gains(const std::string& name) {
  std::istringstream lines(read_file(fixture_path("paper_codes.txt")));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos || line.substr(0, colon) != name) continue;
    std::vector<double> gains;
    std::istringstream numbers(line.substr(colon + 1));
    std::string token;
    while (numbers >> token) gains.push_back(std::strtod(token.c_str(), nullptr));
    return gains;
  }
  ADD_FAILURE() << "no code '" << name << "' in paper_codes.txt";
  return {};
}

namespace {
template <class Values>
double largest_difference(const Values& a, const Values& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  return worst;
}
}  // namespace

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  return largest_difference(a, b);
}

double max_abs_difference(const Image& a, const Image& b) {
  EXPECT_TRUE(a.width == b.width && a.height == b.height && a.channels == b.channels);
  return largest_difference(a.data, b.data);
}

}  // namespace fss::test
