// Private helpers of the image readers in src/io/: an input file's bytes, and
// the memory check before decoding it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fss::detail {

// Whether `size` bytes at `bytes`, the start of a file, are of a format read.
using SignatureTest = bool (*)(const std::uint8_t* bytes, std::size_t size);

// The bytes of input `path`. A directory and an empty file are refused as
// "expected `expected`" ("a PNG file"). The first 8 bytes are read first and
// the rest only when `wanted` accepts them, so that a file of another kind is
// refused by its decoder after 8 bytes, even an endless stream (/dev/zero).
// A file of more than `max_bytes` bytes (0: no limit) is refused (a limit
// fss::Error) before it is read, a stream once that many bytes were read.
// The file is opened once: a pipe or /dev/stdin works.
std::vector<std::uint8_t> read_input_bytes(const std::filesystem::path& path,
                                           const std::string& expected, SignatureTest wanted,
                                           std::size_t max_bytes);

// Refuses (a limit fss::Error) decoding input `name`, `width` x `height`
// pixels, when it needs `needed` bytes, more than `max_bytes` (0: no limit).
void check_decoding_memory(const std::string& name, std::uint64_t width, std::uint64_t height,
                           std::size_t needed, std::size_t max_bytes);

}  // namespace fss::detail
