// Private helpers of the library's writers (output sets, campaign
// directories): creating an output directory with its missing parents, and
// removing exactly those again after a failed run.
#pragma once

#include <filesystem>
#include <system_error>
#include <vector>

namespace fss::detail {

// Creates `dir` and every missing parent; the directories this call created,
// outermost first (one another process made meanwhile is not among them).
// On a failure, `ec` holds the error and the list what was created before it.
std::vector<std::filesystem::path> create_directories_listed(const std::filesystem::path& dir,
                                                             std::error_code& ec);

// Removes the directories of `created` (as create_directories_listed gives
// them), innermost first, each only if it is empty.
void remove_created_directories(const std::vector<std::filesystem::path>& created);

}  // namespace fss::detail
