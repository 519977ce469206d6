#include "mdbrief/base/option_fields.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace mdbrief {
namespace {

// The shortest %g form that reads back as the same double.
std::string realText(double value) {
  char buf[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

std::string boundText(double value, bool integer) {
  if (integer && std::abs(value) < 9e18) return std::to_string(static_cast<long long>(value));
  return realText(value);
}

}  // namespace

bool FieldRange::contains(double value) const {
  if (!(lowOpen ? value > low : value >= low)) return false;  // NaN fails here
  if (!(highOpen ? value < high : value <= high)) return false;
  if (multipleOf > 1 || odd) {
    if (value != std::floor(value)) return false;
    const long long v = static_cast<long long>(value);
    if (multipleOf > 1 && v % multipleOf != 0) return false;
    if (odd && v % 2 == 0) return false;
  }
  return true;
}

std::string FieldRange::text(bool integer) const {
  std::string interval = std::string(lowOpen ? "(" : "[") + boundText(low, integer) + ", " +
                         boundText(high, integer) + (highOpen ? ")" : "]");
  if (odd) return "an odd number in " + interval;
  if (multipleOf > 1) return "a multiple of " + std::to_string(multipleOf) + " in " + interval;
  return "in " + interval;
}

std::string fieldValueText(const FieldValue& value) {
  if (std::holds_alternative<std::monostate>(value)) return "unset";
  if (const auto* i = std::get_if<long long>(&value)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&value)) return realText(*d);
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const auto* s = std::get_if<std::string>(&value)) return "'" + *s + "'";
  std::string list;
  for (const std::string& item : std::get<std::vector<std::string>>(value))
    list += (list.empty() ? "'" : ", '") + item + "'";
  return "[" + list + "]";
}

}  // namespace mdbrief
