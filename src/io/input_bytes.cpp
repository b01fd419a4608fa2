#include "io/input_bytes.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

#include "fss/core/error.h"

namespace fss::detail {

std::vector<std::uint8_t> read_input_bytes(const std::filesystem::path& path,
                                           const std::string& expected, SignatureTest wanted) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error("input '" + name + "' is a directory, expected " + expected);
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    throw_runtime_error("cannot open input '" + name + "': " + std::strerror(errno));
  }
  std::vector<std::uint8_t> bytes(8);
  file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(file.gcount()));
  if (file.bad()) throw_runtime_error("cannot read input '" + name + "'");
  if (bytes.empty()) throw_runtime_error("input '" + name + "' is empty, expected " + expected);
  if (wanted(bytes.data(), bytes.size())) {
    bytes.insert(bytes.end(), std::istreambuf_iterator<char>(file),
                 std::istreambuf_iterator<char>());
    if (file.bad()) throw_runtime_error("cannot read input '" + name + "'");
  }
  return bytes;
}

void check_decoding_memory(const std::string& name, std::uint64_t width, std::uint64_t height,
                           std::size_t needed, std::size_t max_bytes) {
  if (max_bytes > 0 && needed > max_bytes) {
    const auto sizes =
        format_bytes_distinct(static_cast<double>(needed), static_cast<double>(max_bytes));
    throw_limit_error("input '" + name + "' is " + std::to_string(width) + " x " +
                      std::to_string(height) + " pixels: decoding it needs " + sizes.first +
                      ", more than the memory limit of " + sizes.second);
  }
}

}  // namespace fss::detail
