#pragma once
// Names of the options users type (strategies, rules, corrections): one table per enum, looked
// up both ways, so a name can never be parsed one way and printed another.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace vrv {

template <class E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

// Every row named, and no name or value twice: a row left out of a table's initializer list is a
// default one (the first enumerator, no name), which `static_assert(names_complete(kTable))`
// beside each table refuses at compile time.
template <class E, std::size_t N>
constexpr bool names_complete(const NameTable<E, N>& table) {
  for (std::size_t i = 0; i < N; ++i) {
    if (table[i].second.empty()) return false;
    for (std::size_t j = 0; j < i; ++j)
      if (table[j].first == table[i].first || table[j].second == table[i].second) return false;
  }
  return true;
}

template <class E, std::size_t N>
std::optional<E> parse_name(const NameTable<E, N>& table, std::string_view name) {
  for (const auto& [value, n] : table)
    if (n == name) return value;
  return std::nullopt;
}

// Every name, in the table's order, joined by `separator` (", ", or " or " for two): the choices
// an error message offers.
template <class E, std::size_t N>
std::string name_list(const NameTable<E, N>& table, std::string_view separator = ", ") {
  std::string s;
  for (const auto& [value, name] : table) s.append(s.empty() ? "" : separator).append(name);
  return s;
}

template <class E, std::size_t N>
std::string_view name_of(const NameTable<E, N>& table, E value) {
  for (const auto& [v, n] : table)
    if (v == value) return n;
  return "unknown";
}

}  // namespace vrv
