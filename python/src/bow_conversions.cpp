#include "bow_conversions.hpp"

#include <algorithm>
#include <limits>

namespace mdbrief::python {

py::dict bowToPython(const BowVector& bow) {
  py::dict out;
  for (const auto& e : bow) out[py::int_(e.word)] = py::float_(e.value);
  return out;
}

BowVector bowFromPython(const py::handle& mapping, const char* argument) {
  if (!py::isinstance<py::dict>(mapping))
    throw py::type_error(std::string(argument) + ": expected a dict {word: value}");
  BowVector bow;
  for (const auto& item : py::reinterpret_borrow<py::dict>(mapping)) {
    if (!py::isinstance<py::int_>(item.first))
      throw py::value_error(std::string(argument) + ": word " + py::repr(item.first).cast<std::string>() +
                            " is not an integer");
    const auto word = item.first.cast<py::int_>();
    if (word < py::int_(0) || word > py::int_(std::numeric_limits<uint32_t>::max()))
      throw py::value_error(std::string(argument) + ": word " + py::repr(word).cast<std::string>() +
                            " is outside 0..4294967295");
    BowEntry e;
    e.word = word.cast<uint32_t>();
    try {
      e.value = item.second.cast<float>();
    } catch (const py::cast_error&) {
      throw py::value_error(std::string(argument) + ": the value of word " + std::to_string(e.word) +
                            " is not a number");
    }
    bow.push_back(e);
  }
  std::sort(bow.begin(), bow.end(), [](const BowEntry& a, const BowEntry& b) { return a.word < b.word; });
  return bow;
}

}  // namespace mdbrief::python
