#include "io/input_bytes.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "core/huge_pages.h"
#include "fss/core/error.h"

namespace fss::detail {

namespace {

// Refuses input `name` of `bytes` bytes, more than `max_bytes` (0: no
// limit): its bytes alone would exceed the memory limit.
void check_file_bytes(const std::string& name, std::uintmax_t bytes, std::size_t max_bytes) {
  if (max_bytes == 0 || bytes <= max_bytes) return;
  const auto sizes =
      format_bytes_distinct(static_cast<double>(bytes), static_cast<double>(max_bytes));
  throw_limit_error("input '" + name + "' is " + sizes.first + ", more than the memory limit of " +
                    sizes.second);
}

// The rest of a stream (a pipe, a device) after `bytes`, 1 MiB at a time;
// refused once it holds more than `max_bytes` (0: no limit). The blocks are
// joined at the end, so the peak is the bytes and one block.
void read_stream(std::ifstream& file, const std::string& name, std::size_t max_bytes,
                 std::vector<std::uint8_t>& bytes) {
  constexpr std::size_t kBlock = std::size_t{1} << 20;
  std::vector<std::vector<std::uint8_t>> blocks;
  std::size_t total = bytes.size();
  while (file && file.peek() != std::ifstream::traits_type::eof()) {
    if (max_bytes > 0 && total >= max_bytes) {
      throw_limit_error("input '" + name + "' holds more than the memory limit of " +
                        format_bytes(static_cast<double>(max_bytes)));
    }
    std::vector<std::uint8_t>& block = blocks.emplace_back(kBlock);
    file.read(reinterpret_cast<char*>(block.data()), static_cast<std::streamsize>(kBlock));
    block.resize(static_cast<std::size_t>(file.gcount()));
    total += block.size();
  }
  detail::reserve_on_huge_pages(bytes, total);
  for (std::vector<std::uint8_t>& block : blocks) {
    bytes.insert(bytes.end(), block.begin(), block.end());
    std::vector<std::uint8_t>().swap(block);
  }
}

}  // namespace

std::vector<std::uint8_t> read_input_bytes(const std::filesystem::path& path,
                                           const std::string& expected, SignatureTest wanted,
                                           std::size_t max_bytes) {
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
  if (!wanted(bytes.data(), bytes.size())) return bytes;
  // A regular file at once, at its size (refused first if over the limit).
  const bool regular = std::filesystem::is_regular_file(path, ec);
  const std::uintmax_t size = regular ? std::filesystem::file_size(path, ec) : 0;
  if (regular && !ec) {
    check_file_bytes(name, size, max_bytes);
    const std::size_t have = bytes.size();
    const std::size_t total = std::max<std::size_t>(have, static_cast<std::size_t>(size));
    detail::reserve_on_huge_pages(bytes, total);
    bytes.resize(total);
    file.read(reinterpret_cast<char*>(bytes.data() + have),
              static_cast<std::streamsize>(bytes.size() - have));
    bytes.resize(have + static_cast<std::size_t>(file.gcount()));
  }
  read_stream(file, name, max_bytes, bytes);  // what is left: a stream, or a file that grew
  if (file.bad()) throw_runtime_error("cannot read input '" + name + "'");
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
