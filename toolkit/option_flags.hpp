#pragma once
// Command-line flags from an options struct's field table (mdbrief/base/option_fields.hpp): one flag
// per field that has one, its help the field's doc with its range or choices and the default.
// Values are collected during the parse and applied afterwards, so a bad value is reported as
// "<flag> must be in [...], got <value>", the message every other surface gives. A tool that
// takes only a few fields of a table adds each with addFieldFlag: the same name, help and range.
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "mdbrief/base/option_fields.hpp"
#include "toolkit/command_line.hpp"

namespace mdbrief {

// The prefix of fieldRangeCheck's validator names, followed by the field's keyword.
inline constexpr const char* kOptionFieldCheck = "OPTION_FIELD:";

// The check of a tool's own flag for one field of an options table (a flag OptionFlags does not
// make): the field's range (at `defaults`, for a range that depends on other fields) and its
// message, so that the flag takes what the library takes (issue 45: --inlier-threshold took
// [0, 1e6] for a maxPixels in (0, 1000], and 0 or 5000 failed after the work).
template <typename Options>
CLI::Validator fieldRangeCheck(const OptionTable<Options>& table, const std::string& keyword,
                               const Options& defaults = {}) {
  const OptionField<Options>& field = table.at(findField(table, keyword, &OptionField<Options>::keyword));
  const FieldRange range = field.range(defaults);
  const bool integer = field.type == FieldType::Integer;
  return CLI::Validator(
      [range, integer](std::string& value) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v)) return "";  // the type's own conversion reports it
        return range.contains(v) ? "" : "must be " + range.text(integer) + ", got " + value;
      },
      range.text(integer), kOptionFieldCheck + keyword);
}

// A tool's flag for one field of an options table, for a tool that takes a few of the table's
// fields rather than all of them (OptionFlags): the field's flag, its doc (then `note`: what the
// tool also does with the value) and, for a number, its range and fieldRangeCheck, so that the
// flag's name, help and accepted values are the table's and a change to them is one edit there.
// The help reads as OptionFlags' ("<doc>; in [1, 10000000]"). `target` holds the tool's default,
// which the help shows; a range that depends on other fields is taken at `defaults`. A Flag
// field's flag turns the field's default (at `defaults`) around, as OptionFlags' does. Throws
// std::logic_error for a keyword without a flag, or a field of another type.
template <typename Options, typename T>
CLI::Option* addFieldFlag(CLI::App& app, const OptionTable<Options>& table, const std::string& keyword, T& target,
                          const std::string& note = "", const Options& defaults = {}) {
  const std::size_t index = findField(table, keyword, &OptionField<Options>::keyword);
  if (index == table.size() || !table[index].flag)
    throw std::logic_error("addFieldFlag: the table has no flag for '" + keyword + "'");
  const OptionField<Options>& field = table[index];
  const std::string help = field.doc + (note.empty() ? "" : "; " + note);
  if constexpr (std::is_same_v<T, bool>) {
    if (field.type != FieldType::Flag) throw std::logic_error("addFieldFlag: '" + keyword + "' is not a flag");
    const bool turned = !std::get<bool>(field.get(defaults));
    return app.add_flag_function(field.flag, [&target, turned](std::int64_t count) {
      if (count > 0) target = turned;
    })->description(turned ? help : "turn off (on by default): " + help);
  } else {
    const bool integer = field.type == FieldType::Integer;
    if (!integer && field.type != FieldType::Real)
      throw std::logic_error("addFieldFlag: '" + keyword + "' is not a number");
    CLI::Validator check = fieldRangeCheck(table, keyword, defaults);
    check.description("");  // the range is in the help, as OptionFlags puts it
    return app.add_option(field.flag, target, help + "; " + field.range(defaults).text(integer))
        ->check(check)
        ->capture_default_str();
  }
}

template <typename Options>
class OptionFlags {
 public:
  // Adds the flags to app. The object must outlive the parse and stay where it is (the flags
  // write into it).
  void add(CLI::App& app, const OptionTable<Options>& table, const Options& defaults = {}) {
    table_ = &table;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const OptionField<Options>& f = table[i];
      if (!f.flag) continue;
      const FieldValue value = f.get(defaults);
      std::string help = f.doc;
      CLI::Option* option = nullptr;
      switch (f.type) {
        case FieldType::Integer:
          option = app.add_option_function<long long>(f.flag, [this, i](const long long& v) { given_.emplace_back(i, v); });
          help += "; " + f.range(defaults).text(true);
          break;
        case FieldType::Real:
          option = app.add_option_function<double>(f.flag, [this, i](const double& v) { given_.emplace_back(i, v); });
          help += "; " + f.range(defaults).text(false);
          break;
        case FieldType::Flag: {
          // The flag turns the default around.
          const bool turned = !std::get<bool>(value);
          if (!turned) help = "turn off (on by default): " + help;
          option = app.add_flag_function(f.flag, [this, i, turned](std::int64_t count) {
                         if (count > 0) given_.emplace_back(i, turned);
                       })
                       ->check(flagValue());
          break;
        }
        case FieldType::Text:
          option = app.add_option_function<std::string>(f.flag,
                                                        [this, i](const std::string& v) { given_.emplace_back(i, v); });
          break;
        case FieldType::TextList:
          option = app.add_option_function<std::vector<std::string>>(
              f.flag, [this, i](const std::vector<std::string>& v) { given_.emplace_back(i, v); });
          help += " (repeatable)";
          break;
        case FieldType::Choice:
          option = app.add_option_function<std::string>(f.flag,
                                                        [this, i](const std::string& v) { given_.emplace_back(i, v); })
                       ->check(CLI::IsMember(f.choices));
          break;
      }
      option->description(help);
      if (const auto* i = std::get_if<long long>(&value)) option->default_str(std::to_string(*i));
      if (const auto* d = std::get_if<double>(&value)) {
        std::ostringstream shown;  // six digits: a float member's default would show its binary tail
        shown << *d;
        option->default_str(shown.str());
      }
      if (const auto* s = std::get_if<std::string>(&value); s && !s->empty()) option->default_str(*s);
      for (const auto& [old, now] : kRenamedFlags)
        if (now == std::string(f.flag)) addRenamedFlag(app, old, now);
    }
  }

  // Whether any of the flags was given: a command refuses them without the mode they tune.
  bool anyGiven() const { return !given_.empty(); }

  // `options` with the given flags applied (in command-line order), then checked by `validate`.
  // Throws OptionError named by the flag.
  template <typename Validate>
  Options apply(Options options, Validate validate) const {
    const OptionTable<Options>& table = *table_;
    const auto flagOf = [&](std::size_t i) { return std::string(table[i].flag ? table[i].flag : table[i].keyword); };
    try {
      for (const auto& [i, v] : given_) setField(table, i, options, v, flagOf(i));
      validate(options);
    } catch (const OptionError& e) {
      throw OptionError(e.field(), flagOf(e.field()), e.problem());
    }
    return options;
  }

 private:
  // Flags spelt otherwise by an earlier release: {old, new}. nfeatures is one name in C++,
  // Python and on the command line.
  static constexpr std::pair<const char*, const char*> kRenamedFlags[] = {{"--features", "--nfeatures"}};

  // CLI11 turns a flag's value (`--make-default=yes`, `make-default = yes` in a config) into a
  // count with std::stoll, which throws std::invalid_argument past the parse's error handling on
  // anything but its true/false words and integers; checked first, a bad one is a parse error
  // naming the flag.
  static CLI::Validator flagValue() {
    return CLI::Validator(
        [](std::string& v) -> std::string {
          try {
            CLI::detail::to_flag_value(v);
          } catch (const std::exception&) {
            return "'" + v + "' is neither true nor false";
          }
          return {};
        },
        "BOOLEAN");
  }

  const OptionTable<Options>* table_ = nullptr;
  std::vector<std::pair<std::size_t, FieldValue>> given_;
};

}  // namespace mdbrief
