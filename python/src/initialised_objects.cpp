#include <cstring>

#include "bindings.hpp"

namespace mdbrief::python {
namespace {

bool named(PyObject* name, const char* text) {
  const char* utf8 = PyUnicode_Check(name) ? PyUnicode_AsUTF8(name) : nullptr;
  if (!utf8) PyErr_Clear();
  return utf8 && std::strcmp(utf8, text) == 0;
}

// The attributes an uninitialised object needs to become one: construction and unpickling.
bool initialises(PyObject* name) {
  return named(name, "__init__") || named(name, "__setstate__") || named(name, "__class__");
}

// Constructed objects own a holder; a reference to a C++ object (db.vocabulary) owns nothing.
// Only an object made by __new__ owns and holds nothing.
bool initialised(PyObject* self) {
  auto* instance = reinterpret_cast<py::detail::instance*>(self);
  return !instance->owned || instance->get_value_and_holder().holder_constructed();
}

void setNotInitialisedError(PyObject* self) {
  const char* type = Py_TYPE(self)->tp_name;
  PyErr_Format(PyExc_TypeError,
               "this %s object was never initialised (made with __new__ alone): create it by calling %s(...)", type,
               type);
}

// pybind11 gives an uninitialised object fresh, unconstructed memory as its C++ value, so every
// attribute but those that initialise it is refused.
// __setstate__ on a live object was ignored without a word (pybind11 initialises only once).
PyObject* initialisedGetattro(PyObject* self, PyObject* name) {
  if (!initialised(self) && !initialises(name)) {
    setNotInitialisedError(self);
    return nullptr;
  }
  if (initialised(self) && named(name, "__setstate__")) {
    PyErr_Format(PyExc_TypeError, "%s.__setstate__ only initialises an object being unpickled; this one is already",
                 Py_TYPE(self)->tp_name);
    return nullptr;
  }
  return PyObject_GenericGetAttr(self, name);
}

}  // namespace

void requireInitialised(const py::handle& self) {
  if (initialised(self.ptr())) return;
  setNotInitialisedError(self.ptr());
  throw py::error_already_set();
}

py::custom_type_setup initialisedObjectsOnly() {
  return py::custom_type_setup([](PyHeapTypeObject* type) { type->ht_type.tp_getattro = initialisedGetattro; });
}

}  // namespace mdbrief::python
