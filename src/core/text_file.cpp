#include "core/text_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include "fss/core/error.h"

namespace fss::detail {

namespace {

// "16 MiB", "512 KiB", "100 bytes".
std::string size_text(std::size_t bytes) {
  if (bytes % (std::size_t{1} << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes % (std::size_t{1} << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

std::string read_bounded_text_file(const std::filesystem::path& path, std::size_t max_bytes,
                                   const std::string& label, const std::string& shown,
                                   const std::string& expected) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error(label + " '" + shown + "' is a directory, expected " + expected);
  }
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw_runtime_error("cannot open " + label + " '" + shown + "': " + std::strerror(errno));
  std::string text;
  std::vector<char> buffer(std::size_t{1} << 16);
  while (file.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) ||
         file.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(file.gcount()));
    if (text.size() > max_bytes) {
      std::string message = label;
      message += " '" + shown + "' is larger than " + size_text(max_bytes);
      message += ": expected " + expected;
      throw_runtime_error(message);
    }
  }
  if (file.bad()) throw_runtime_error("cannot read " + label + " '" + shown + "'");
  return text;
}

}  // namespace fss::detail
