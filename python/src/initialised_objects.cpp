#include <cstring>

#include "bindings.hpp"

namespace mdbrief::python {
namespace {

// The attributes an uninitialised object needs to become one: construction and unpickling.
bool initialises(PyObject* name) {
  const char* text = PyUnicode_Check(name) ? PyUnicode_AsUTF8(name) : nullptr;
  if (!text) {
    PyErr_Clear();
    return false;
  }
  return std::strcmp(text, "__init__") == 0 || std::strcmp(text, "__setstate__") == 0 ||
         std::strcmp(text, "__class__") == 0;
}

bool initialised(PyObject* self) {
  return reinterpret_cast<py::detail::instance*>(self)->get_value_and_holder().holder_constructed();
}

void setNotInitialisedError(PyObject* self) {
  const char* type = Py_TYPE(self)->tp_name;
  PyErr_Format(PyExc_TypeError,
               "this %s object was never initialised (made with __new__ alone): create it by calling %s(...)", type,
               type);
}

// pybind11 gives an uninitialised object fresh, unconstructed memory as its C++ value, so every
// attribute but those that initialise it is refused.
PyObject* initialisedGetattro(PyObject* self, PyObject* name) {
  if (!initialised(self) && !initialises(name)) {
    setNotInitialisedError(self);
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
