#pragma once
// Python keywords from an options struct's field table (mdbrief/base/option_fields.hpp): the
// keyword names, their types, the defaults shown in docstrings, and errors that name the keyword
// (the table says which field failed, so no message is parsed).
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <type_traits>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief::python {

// The keyword's value as the field's type: TypeError for a wrong kind of object (bool is a
// Python int: refused for numbers, and numbers for flags), ValueError naming the keyword and
// the field's range for an integer beyond any C++ integer. Text fields (files, folders, names)
// take any path: str, bytes or os.PathLike (pathFrom, which refuses a NUL byte).
template <typename Options>
FieldValue keywordValue(const OptionField<Options>& field, const Options& options, const py::handle& value) {
  const std::string name = field.keyword;
  const bool isBool = py::isinstance<py::bool_>(value);
  switch (field.type) {
    case FieldType::Integer:
      if (isBool || !py::isinstance<py::int_>(value)) throw py::type_error(name + " must be an int");
      try {
        return value.cast<long long>();
      } catch (const py::cast_error&) {
        throw py::value_error(name + " must be " + field.range(options).text(true) + ", got " +
                              std::string(py::str(value)));
      }
    case FieldType::Real:
      if (value.is_none() && field.unsettable) return std::monostate{};  // turns the option off
      if (isBool || !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)))
        throw py::type_error(name + " must be a number");
      return value.cast<double>();
    case FieldType::Flag:
      if (!isBool) throw py::type_error(name + " must be True or False");
      return value.cast<bool>();
    case FieldType::Text:
      return pathFrom(value, field.keyword);
    case FieldType::Choice:
      if (!py::isinstance<py::str>(value)) throw py::type_error(name + " must be a str");
      return value.cast<std::string>();
    case FieldType::TextList: {
      if (isPath(value)) return std::vector<std::string>{pathFrom(value, field.keyword)};
      if (!py::isinstance<py::iterable>(value)) throw py::type_error(name + " must be a path or a list of them");
      std::vector<std::string> items;
      for (const py::handle item : value) {
        if (!isPath(item)) throw py::type_error(name + " must be a path or a list of them");
        items.push_back(pathFrom(item, field.keyword));
      }
      if (items.empty()) throw py::value_error(name + " is empty");
      return items;
    }
  }
  throw py::type_error(name + ": unsupported option type");
}

// ValueError "<keyword> <problem>" for an OptionError raised on `table`.
template <typename Options>
[[noreturn]] void raiseForKeyword(const OptionTable<Options>& table, const OptionError& e) {
  throw py::value_error(std::string(table.at(e.field()).keyword) + " " + e.problem());
}

// `options` changed by keyword arguments (the table's keywords; `skip` names keywords the caller
// reads itself), validated. TypeError for an unknown keyword, as Python's own calls raise.
template <typename Options, typename Validate>
Options optionsFromKeywords(const OptionTable<Options>& table, const py::kwargs& kwargs, const char* callable,
                            Validate validate, const std::vector<std::string>& skip = {}, Options options = {}) {
  try {
    for (const auto& [key, value] : kwargs) {
      const std::string name = py::str(key);
      if (std::find(skip.begin(), skip.end(), name) != skip.end()) continue;
      const std::size_t i = findField(table, name, &OptionField<Options>::keyword);
      if (i == table.size())
        throw py::type_error(std::string(callable) + "() got an unexpected keyword argument '" + name + "'");
      setField(table, i, options, keywordValue(table[i], options, value), name);
    }
    validate(options);
  } catch (const OptionError& e) {
    raiseForKeyword(table, e);
  }
  return options;
}

// Text as the file system spells it (pathText), so any path a keyword took reads back.
inline py::object keywordObject(const FieldValue& value) {
  return std::visit(
      [](const auto& v) -> py::object {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return py::none();
        } else if constexpr (std::is_same_v<T, std::string>) {
          return pathText(v);
        } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          py::list items;
          for (const std::string& item : v) items.append(pathText(item));
          return std::move(items);
        } else {
          return py::cast(v);
        }
      },
      value);
}

// Every keyword and its value.
template <typename Options>
py::dict keywordDict(const OptionTable<Options>& table, const Options& options) {
  py::dict d;
  for (const OptionField<Options>& f : table) d[f.keyword] = keywordObject(f.get(options));
  return d;
}

// One docstring line per keyword: "name=default  doc (range)".
template <typename Options>
std::string keywordDoc(const OptionTable<Options>& table, const Options& defaults) {
  std::ostringstream doc;
  for (const OptionField<Options>& f : table) {
    doc << "    " << f.keyword << "=" << std::string(py::repr(keywordObject(f.get(defaults)))) << "  "
        << f.doc;
    if (f.type == FieldType::Integer || f.type == FieldType::Real)
      doc << "; " << f.range(defaults).text(f.type == FieldType::Integer);
    if (f.type == FieldType::Choice) {
      doc << ": ";
      for (std::size_t i = 0; i < f.choices.size(); ++i) doc << (i ? " | " : "") << f.choices[i];
    }
    doc << "\n";
  }
  return doc.str();
}

// MdBrief's keywords: the library's table with the detection method spelt `method`, as
// DetectorOptions::method and the README spell it (the table's `detector` is the command line's
// --detector). bind_features.cpp.
const OptionTable<MdBriefOptions>& mdBriefKeywords();

}  // namespace mdbrief::python
