#pragma once
// The parts of the `mdbrief` Python module, one per concept; module.cpp puts them together.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace mdbrief::python {

namespace py = pybind11;

void bindCamera(py::module_& m);
void bindDatabase(py::module_& m);
void bindFeatures(py::module_& m);
void bindMatching(py::module_& m);
void bindOptions(py::module_& m);
void bindPatterns(py::module_& m);
void bindPresets(py::module_& m);
void bindSimdLevel(py::module_& m);
void bindVocabulary(py::module_& m);
// Registers the module's translation of C++ exceptions (exception_translation.cpp).
void translateExceptions();

}  // namespace mdbrief::python
