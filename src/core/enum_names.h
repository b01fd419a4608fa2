// Private helper: one table of names per enum class, which gives both its
// to_string and its *_from_string, so that the two cannot disagree.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace fss::detail {

// Every value of an enum with its name; the first entry is the fallback.
template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, std::string_view>, N>;

// The name of `value`; the first entry's name for a value not in `names`.
template <typename Enum, std::size_t N>
std::string enum_name(const EnumNames<Enum, N>& names, Enum value) {
  for (const auto& [entry, name] : names) {
    if (entry == value) return std::string(name);
  }
  return std::string(names.front().second);
}

// The value named `text` exactly; nullopt when no entry has that name.
template <typename Enum, std::size_t N>
std::optional<Enum> enum_from_name(const EnumNames<Enum, N>& names, std::string_view text) {
  for (const auto& [entry, name] : names) {
    if (name == text) return entry;
  }
  return std::nullopt;
}

}  // namespace fss::detail
