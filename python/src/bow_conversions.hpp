#pragma once
// Bags of words (bow_vector.hpp) in Python: a dict {word: value}, in ascending word order.
#include "bindings.hpp"
#include "mdbrief/recognition/bow_vector.hpp"

namespace mdbrief::python {

py::dict bowToPython(const BowVector& bow);
// A mapping {word: value} as a BowVector sorted by word. Raises ValueError naming `argument` for
// a word that is not an integer in 0..2^32-1 or a value that is not a number; the Database checks
// the rest (words of its vocabulary, values finite and > 0).
BowVector bowFromPython(const py::handle& mapping, const char* argument);

}  // namespace mdbrief::python
