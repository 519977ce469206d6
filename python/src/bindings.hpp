#pragma once
// The parts of the `mdbrief` Python module, one per concept; module.cpp puts them together.
#include <cstddef>
#include <memory>
#include <typeinfo>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::python {

namespace py = pybind11;

void bindCamera(py::module_& m);
void bindDatabase(py::module_& m);
void bindFeatures(py::module_& m);
void bindGeometry(py::module_& m);
void bindMatching(py::module_& m);
void bindMatchRefinement(py::module_& m);
void bindOptions(py::module_& m);
void bindPatterns(py::module_& m);
void bindPresets(py::module_& m);
void bindSimdLevel(py::module_& m);
void bindVocabulary(py::module_& m);
// Every class of the module is declared with boundClass(m, "Name", ...) instead of
// py::class_<T, ...>(m, "Name", ...); finishClasses, at the end of the module's initialisation,
// refuses to import a module with a class declared otherwise.
//
// An object made with Cls.__new__(Cls) and never initialised holds no C++ object; pybind11 would
// hand fresh, unconstructed memory to any function taking it (as self or as an argument), which
// crashed or read garbage. boundClass makes that memory's allocation (the type's operator_new,
// which pybind11 2.10 calls only for this, in type_caster_generic::load_value) raise TypeError
// naming the class instead, so every function of the module refuses such an object.
// std::shared_ptr<T> arguments, which pybind11 loads without the value, are checked by
// CheckedSharedCaster below. tests/python/test_uninitialised_objects.py feeds such objects to
// every function and method, so a pybind11 that allocates elsewhere fails there.
[[noreturn]] void raiseNeverInitialised(PyTypeObject* type);
void guardClass(const std::type_info& type, void* (*refuseValue)(std::size_t));

template <typename T>
void* refuseUninitialisedValue(std::size_t) {
  raiseNeverInitialised(py::detail::get_type_info(typeid(T))->type);
}

template <typename T, typename... Options, typename... Extra>
py::class_<T, Options...> boundClass(py::handle scope, const char* name, const Extra&... extra) {
  py::class_<T, Options...> cls(scope, name, extra...);
  guardClass(typeid(T), &refuseUninitialisedValue<T>);
  return cls;
}

// After every class's methods are defined: checks that each class of `m` came through
// boundClass (ImportError naming it otherwise) and makes __init__ and __setstate__ on an object
// already initialised raise TypeError (pybind11 ignored the call without a word).
void finishClasses(py::module_& m);

// Raises TypeError, as refuseUninitialisedValue does, when `object` is an instance of a bound
// class that was never initialised.
void requireInitialised(const py::handle& object);

// std::shared_ptr<T> as an argument: pybind11's holder caster reads only the holder, and for an
// object never initialised raised "Unable to cast from non-held to held instance".
template <typename T>
class CheckedSharedCaster : public py::detail::copyable_holder_caster<T, std::shared_ptr<T>> {
 public:
  bool load(py::handle source, bool convert) {
    requireInitialised(source);
    return py::detail::copyable_holder_caster<T, std::shared_ptr<T>>::load(source, convert);
  }
};

// Registers the module's translation of C++ exceptions (exception_translation.cpp).
void translateExceptions();

}  // namespace mdbrief::python

// Every class held by std::shared_ptr (py::class_<T, std::shared_ptr<T>>) that a function takes
// as std::shared_ptr<T>. Every binding file includes this header, so every use sees it.
namespace pybind11::detail {
template <>
class type_caster<std::shared_ptr<mdbrief::Camera>> : public mdbrief::python::CheckedSharedCaster<mdbrief::Camera> {};
}  // namespace pybind11::detail
