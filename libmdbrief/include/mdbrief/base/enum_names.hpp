#pragma once
// The names users type for the options' enums (FileStorage, the command line, Python). Each
// enum's header keeps one table of {value, name} next to the enum; toString(), the parse
// functions and the command line's choices all read that table, so a name lives in one place.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace mdbrief {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value`. Throws std::invalid_argument for a value the table lacks.
template <typename Enum, std::size_t N>
std::string nameOf(Enum value, const EnumName<Enum> (&table)[N]) {
  for (const EnumName<Enum>& entry : table)
    if (entry.value == value) return entry.name;
  throw std::invalid_argument("unknown enum value");
}

// The value named `name`. Throws std::invalid_argument "<what> '<name>' is not one of: ..."
// listing the names in table order.
template <typename Enum, std::size_t N>
Enum parseName(const std::string& name, const EnumName<Enum> (&table)[N], const char* what) {
  std::string known;
  for (const EnumName<Enum>& entry : table) {
    if (name == entry.name) return entry.value;
    known += known.empty() ? entry.name : std::string(", ") + entry.name;
  }
  throw std::invalid_argument(std::string(what) + " '" + name + "' is not one of: " + known);
}

// Every name, in table order (e.g. a command line's choices).
template <typename Enum, std::size_t N>
std::vector<std::string> namesOf(const EnumName<Enum> (&table)[N]) {
  std::vector<std::string> names;
  for (const EnumName<Enum>& entry : table) names.emplace_back(entry.name);
  return names;
}

}  // namespace mdbrief
