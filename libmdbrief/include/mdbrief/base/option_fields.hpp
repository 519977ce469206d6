#pragma once
// One table of fields per options struct: each field's member, FileStorage section, Python
// keyword, command-line flag, doc, type and accepted values. validate(), FileStorage, the
// Python keywords and the command-line flags all read the table, so adding an option is one
// entry plus its use, and every surface checks the same bounds with the same message:
//     "<the option as that surface spells it> must be in [1, 10000000], got -1".
// A bad value throws OptionError, which carries the field's index, so each surface names the
// option its own way without parsing messages.
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "mdbrief/base/enum_names.hpp"

namespace mdbrief {

enum class FieldType {
  Integer,   // any integral member
  Real,      // double or float, or std::optional of one (unset = off)
  Flag,      // bool
  Text,      // std::string
  TextList,  // std::vector<std::string> (folders, files)
  Choice,    // an enum, by the names of its EnumName table
};

// The values a numeric field accepts: low..high, either end open; integers may have to be odd or
// a multiple of a step.
struct FieldRange {
  double low = 0, high = 0;
  bool lowOpen = false, highOpen = false;
  long long multipleOf = 1;
  bool odd = false;

  static FieldRange closed(double low, double high) { return {low, high}; }
  static FieldRange open(double low, double high) { return {low, high, true, true}; }
  static FieldRange openLow(double low, double high) { return {low, high, true, false}; }

  bool contains(double value) const;
  // "in [1, 10000000]", "an odd number in [3, 15]", "a multiple of 32 in [32, 512]".
  std::string text(bool integer) const;
};

// Unset (an optional field that is off), integer, real, flag, text, text list or choice name.
using FieldValue = std::variant<std::monostate, long long, double, bool, std::string, std::vector<std::string>>;

// A value as messages print it: integers as integers, reals in the shortest form that reads
// back the same, names quoted.
std::string fieldValueText(const FieldValue& value);

// A bad option value. what() = name + " " + problem(); field() is its index in the table that
// was checked, so a surface can name the option its own way: problem() is the same everywhere.
class OptionError : public std::invalid_argument {
 public:
  OptionError(std::size_t field, const std::string& name, std::string problem)
      : std::invalid_argument(name + " " + problem), field_(field), problem_(std::move(problem)) {}
  std::size_t field() const { return field_; }
  // "must be in [1, 10000000], got -1" or "must be one of: fast, agast, got 'x'".
  const std::string& problem() const { return problem_; }

 private:
  std::size_t field_;
  std::string problem_;
};

template <typename Options>
struct OptionField {
  std::string member;   // path of the C++ member ("pyramid.levels"); its last part is the FileStorage key
  const char* section;  // FileStorage node of the key ("" = the node itself)
  const char* keyword;  // Python keyword
  // Command-line flag ("--nfeatures"); nullptr = not on the command line. A Flag field's flag
  // turns its default around (--spread, --no-orientation).
  const char* flag;
  const char* doc;
  FieldType type;
  std::vector<std::string> choices;                  // Choice: the accepted names
  std::function<FieldRange(const Options&)> range;   // Integer, Real: may depend on other fields
  std::function<FieldValue(const Options&)> get;
  // Stores the value (of the type's FieldValue alternative; an Integer also takes a Real with an
  // integral value). Returns false when the member cannot hold it (an integer beyond its type);
  // a Choice throws std::invalid_argument for an unknown name.
  std::function<bool(Options&, const FieldValue&)> set;
  bool unsettable = false;  // Real: a std::optional member, which may be unset (off)

  // The FileStorage key: the member's last part.
  std::string key() const {
    const auto dot = member.rfind('.');
    return dot == std::string::npos ? member : member.substr(dot + 1);
  }
};

template <typename Options>
using OptionTable = std::vector<OptionField<Options>>;

// What is wrong with the field's current value ("must be in [...], got v"), or nothing.
template <typename Options>
std::optional<std::string> fieldProblem(const OptionField<Options>& field, const Options& options) {
  if (field.type != FieldType::Integer && field.type != FieldType::Real) return std::nullopt;
  const FieldValue value = field.get(options);
  if (std::holds_alternative<std::monostate>(value)) return std::nullopt;
  const double v = std::holds_alternative<long long>(value) ? static_cast<double>(std::get<long long>(value))
                                                            : std::get<double>(value);
  const FieldRange range = field.range(options);
  if (range.contains(v)) return std::nullopt;
  return "must be " + range.text(field.type == FieldType::Integer) + ", got " + fieldValueText(value);
}

// Throws OptionError for the first field (table order) whose value is out of range, named
// structName::member.
template <typename Options>
void validateFields(const OptionTable<Options>& table, const Options& options, const char* structName) {
  for (std::size_t i = 0; i < table.size(); ++i)
    if (const auto problem = fieldProblem(table[i], options))
      throw OptionError(i, std::string(structName) + "::" + table[i].member, *problem);
}

// Sets field `index` of options to value. Throws OptionError (named `name`) for an integer its
// member cannot hold (out of range whatever the other fields are) or an unknown choice.
template <typename Options>
void setField(const OptionTable<Options>& table, std::size_t index, Options& options, const FieldValue& value,
              const std::string& name) {
  const OptionField<Options>& field = table.at(index);
  if (field.type == FieldType::Choice) {
    try {
      field.set(options, value);
    } catch (const std::invalid_argument&) {
      std::string known;
      for (const std::string& c : field.choices) known += (known.empty() ? "" : ", ") + c;
      throw OptionError(index, name, "must be one of: " + known + ", got " + fieldValueText(value));
    }
    return;
  }
  if (!field.set(options, value))
    throw OptionError(index, name,
                      "must be " + field.range(options).text(field.type == FieldType::Integer) + ", got " +
                          fieldValueText(value));
}

// The index of the field with this keyword (or flag, or member), or table.size().
template <typename Options>
std::size_t findField(const OptionTable<Options>& table, const std::string& name,
                      const char* OptionField<Options>::*spelling) {
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i].*spelling && name == table[i].*spelling) return i;
  return table.size();
}

// --- Building a table -------------------------------------------------------------------
// access: a generic lambda [](auto& o) -> auto& { return o.member; }, so it serves const
// options (get) and mutable ones (set).

namespace detail {

template <typename T>
bool storeInteger(T& member, const FieldValue& value) {
  long long v = 0;
  if (const auto* i = std::get_if<long long>(&value)) {
    v = *i;
  } else {
    const double d = std::get<double>(value);
    if (!(d >= -9.2e18 && d <= 9.2e18) || d != static_cast<double>(static_cast<long long>(d))) return false;
    v = static_cast<long long>(d);
  }
  if constexpr (std::is_unsigned_v<T>) {
    if (v < 0 || static_cast<unsigned long long>(v) > std::numeric_limits<T>::max()) return false;
  } else {
    if (v < static_cast<long long>(std::numeric_limits<T>::min()) ||
        v > static_cast<long long>(std::numeric_limits<T>::max()))
      return false;
  }
  member = static_cast<T>(v);
  return true;
}

inline double realOf(const FieldValue& value) {
  if (const auto* i = std::get_if<long long>(&value)) return static_cast<double>(*i);
  return std::get<double>(value);
}

}  // namespace detail

template <typename Options, typename Access>
OptionField<Options> integerField(const char* member, const char* section, const char* keyword, const char* flag,
                                  const char* doc, std::function<FieldRange(const Options&)> range, Access access) {
  return {member, section, keyword, flag, doc, FieldType::Integer, {}, std::move(range),
          [access](const Options& o) -> FieldValue { return static_cast<long long>(access(o)); },
          [access](Options& o, const FieldValue& v) { return detail::storeInteger(access(o), v); }};
}

template <typename Options, typename Access>
OptionField<Options> integerField(const char* member, const char* section, const char* keyword, const char* flag,
                                  const char* doc, FieldRange range, Access access) {
  return integerField<Options>(member, section, keyword, flag, doc,
                               std::function<FieldRange(const Options&)>([range](const Options&) { return range; }),
                               access);
}

template <typename Options, typename Access>
OptionField<Options> realField(const char* member, const char* section, const char* keyword, const char* flag,
                               const char* doc, FieldRange range, Access access) {
  using Member = std::remove_reference_t<decltype(access(std::declval<Options&>()))>;
  auto get = [access](const Options& o) -> FieldValue {
    const Member& m = access(o);
    if constexpr (std::is_arithmetic_v<Member>) {
      return static_cast<double>(m);
    } else {
      if (!m) return std::monostate{};
      return static_cast<double>(*m);
    }
  };
  auto set = [access](Options& o, const FieldValue& v) {
    Member& m = access(o);
    if constexpr (std::is_arithmetic_v<Member>) {
      m = static_cast<Member>(detail::realOf(v));
    } else if (std::holds_alternative<std::monostate>(v)) {
      m.reset();
    } else {
      m = static_cast<typename Member::value_type>(detail::realOf(v));
    }
    return true;
  };
  return {member, section, keyword, flag, doc, FieldType::Real, {},
          [range](const Options&) { return range; }, get, set, !std::is_arithmetic_v<Member>};
}

template <typename Options, typename Access>
OptionField<Options> flagField(const char* member, const char* section, const char* keyword, const char* flag,
                               const char* doc, Access access) {
  return {member, section, keyword, flag, doc, FieldType::Flag, {}, {},
          [access](const Options& o) -> FieldValue { return static_cast<bool>(access(o)); },
          [access](Options& o, const FieldValue& v) {
            access(o) = std::get<bool>(v);
            return true;
          }};
}

template <typename Options, typename Access>
OptionField<Options> textField(const char* member, const char* section, const char* keyword, const char* flag,
                               const char* doc, Access access) {
  return {member, section, keyword, flag, doc, FieldType::Text, {}, {},
          [access](const Options& o) -> FieldValue { return std::string(access(o)); },
          [access](Options& o, const FieldValue& v) {
            access(o) = std::get<std::string>(v);
            return true;
          }};
}

// A list of texts; the member may be a vector of anything constructible from and convertible to
// std::string (std::filesystem::path).
template <typename Options, typename Access>
OptionField<Options> textListField(const char* member, const char* section, const char* keyword, const char* flag,
                                   const char* doc, Access access) {
  return {member, section, keyword, flag, doc, FieldType::TextList, {}, {},
          [access](const Options& o) -> FieldValue {
            std::vector<std::string> out;
            for (const auto& item : access(o)) out.emplace_back(std::string(item));
            return out;
          },
          [access](Options& o, const FieldValue& v) {
            auto& m = access(o);
            m.clear();
            for (const std::string& item : std::get<std::vector<std::string>>(v)) m.emplace_back(item);
            return true;
          }};
}

template <typename Options, typename Enum, std::size_t N, typename Access>
OptionField<Options> choiceField(const char* member, const char* section, const char* keyword, const char* flag,
                                 const char* doc, const EnumName<Enum> (&names)[N], Access access) {
  const EnumName<Enum>* table = names;
  return {member, section, keyword, flag, doc, FieldType::Choice, namesOf(names), {},
          [access, table](const Options& o) -> FieldValue {
            const Enum value = access(o);
            for (std::size_t i = 0; i < N; ++i)
              if (table[i].value == value) return std::string(table[i].name);
            throw std::invalid_argument("unknown enum value");
          },
          [access, table](Options& o, const FieldValue& v) {
            const std::string& name = std::get<std::string>(v);
            for (std::size_t i = 0; i < N; ++i)
              if (name == table[i].name) {
                access(o) = table[i].value;
                return true;
              }
            throw std::invalid_argument("'" + name + "' is not a choice");
          }};
}

// The fields of a nested struct (Outer::*inner, reached by `access`) as fields of Outer: member
// becomes prefix + "." + member; an empty section becomes `section`. Every member of the field is
// named below, so that -Wmissing-field-initializers reports one added to OptionField and not
// carried here (`unsettable` was not, and a nested optional could not be turned off).
template <typename Outer, typename Inner, typename Access>
void appendNested(OptionTable<Outer>& out, const OptionTable<Inner>& inner, const char* prefix, const char* section,
                  Access access) {
  for (const OptionField<Inner>& f : inner) {
    OptionField<Outer> g{std::string(prefix) + "." + f.member,
                         *f.section ? f.section : section,
                         f.keyword,
                         f.flag,
                         f.doc,
                         f.type,
                         f.choices,
                         {},
                         {},
                         {},
                         f.unsettable};
    if (f.range) g.range = [access, r = f.range](const Outer& o) { return r(access(o)); };
    g.get = [access, get = f.get](const Outer& o) { return get(access(o)); };
    g.set = [access, set = f.set](Outer& o, const FieldValue& v) { return set(access(o), v); };
    out.push_back(std::move(g));
  }
}

}  // namespace mdbrief
