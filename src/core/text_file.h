// Reading a small text file of user data (a code, a list of velocities) with its size bounded
// as it is read. Internal to the library.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace fss::detail {

// The bytes of `path`, read in blocks and refused past `max_bytes` (so that an endless stream
// such as /dev/zero is refused too). Throws a runtime fss::Error naming "`label` 'shown'" for a
// directory, a file that cannot be opened or read, or one over the bound ("... is larger than 16
// MiB: expected `expected`").
std::string read_bounded_text_file(const std::filesystem::path& path, std::size_t max_bytes,
                                   const std::string& label, const std::string& shown,
                                   const std::string& expected);

}  // namespace fss::detail
