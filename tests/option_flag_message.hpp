#pragma once
// The message of a bad value given to a flag made from an option table's field
// (toolkit/option_flags.hpp addFieldFlag, fieldRangeCheck), built from the table, so that a test
// expects what the table says and not a copy of it.
#include <string>

#include "mdbrief/base/option_fields.hpp"

namespace mdbrief::testing {

// "--nfeatures: must be in [1, 10000000], got 0" for (detectorOptionFields(), "nfeatures", "0").
template <typename Options>
std::string optionFlagMessage(const OptionTable<Options>& table, const std::string& keyword, const std::string& value) {
  const OptionField<Options>& field = table.at(findField(table, keyword, &OptionField<Options>::keyword));
  return std::string(field.flag) + ": must be " + field.range(Options{}).text(field.type == FieldType::Integer) +
         ", got " + value;
}

}  // namespace mdbrief::testing
