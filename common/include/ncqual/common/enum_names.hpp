// SPDX-License-Identifier: Apache-2.0
// Names of enumerators kept in one array per enum (in enumerator order), instead of a switch per
// direction: name_of for printing, enum_named for reading.
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace ncqual {

// The name of `value`, or `unknown` when it is not an enumerator the array names.
template <typename Enum, std::size_t N>
constexpr std::string_view name_of(const std::array<std::string_view, N>& names, Enum value,
                                   std::string_view unknown = "?") {
  const auto i = static_cast<long long>(value);
  return i >= 0 && static_cast<std::size_t>(i) < N ? names[static_cast<std::size_t>(i)] : unknown;
}

// The enumerator named `text`; nothing when the array has no such name.
template <typename Enum, std::size_t N>
constexpr std::optional<Enum> enum_named(const std::array<std::string_view, N>& names,
                                         std::string_view text) {
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i] == text) return static_cast<Enum>(i);
  }
  return std::nullopt;
}

}  // namespace ncqual
