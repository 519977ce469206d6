#pragma once
// The parts of the `mdbrief` Python module, one per concept; module.cpp puts them together.
#include <functional>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace mdbrief::python {

namespace py = pybind11;

void bindCamera(py::module_& m);
void bindDatabase(py::module_& m);
void bindFeatures(py::module_& m);
void bindGeometry(py::module_& m);
void bindMatching(py::module_& m);
void bindOptions(py::module_& m);
void bindPatterns(py::module_& m);
void bindPresets(py::module_& m);
void bindSimdLevel(py::module_& m);
void bindVocabulary(py::module_& m);
// For every py::class_: an object made with Cls.__new__(Cls) and never initialised holds no C++
// object, and its methods and properties read garbage or crashed (issue 29). With this, such an
// object raises TypeError for every attribute but __init__ and __setstate__ (construction and
// unpickling, which initialise it); __setstate__ of an initialised object, which pybind11
// ignored, raises TypeError too.
py::custom_type_setup initialisedObjectsOnly();
// Throws TypeError, as initialisedObjectsOnly's check, when self was never initialised.
void requireInitialised(const py::handle& self);
// f(const T&) as a special method (__repr__, __len__): Python calls those through the type's
// slots, past initialisedObjectsOnly's check, so the wrapper checks self first.
template <typename T, typename F>
auto onInitialised(F f) {
  return [f](const py::handle& self) {
    requireInitialised(self);
    return std::invoke(f, self.cast<const T&>());
  };
}
// Registers the module's translation of C++ exceptions (exception_translation.cpp).
void translateExceptions();

}  // namespace mdbrief::python
