// The guards behind boundClass and finishClasses (bindings.hpp): objects made by __new__ alone
// and objects initialised twice.
#include <deque>
#include <set>
#include <string>

#include "bindings.hpp"

namespace mdbrief::python {
namespace {

// The Python types declared with boundClass.
std::set<PyTypeObject*>& guardedTypes() {
  static std::set<PyTypeObject*> types;
  return types;
}

// "mdbrief.Camera": the package's name of a class of the module.
std::string publicName(PyTypeObject* type) {
  const std::string full = type->tp_name;
  return "mdbrief." + full.substr(full.rfind('.') + 1);
}

// Constructed objects own a holder; a reference to a C++ object (db.vocabulary) owns nothing.
// Only an object made by __new__ owns and holds nothing.
bool initialised(PyObject* object) {
  auto* instance = reinterpret_cast<py::detail::instance*>(object);
  return !instance->owned || instance->get_value_and_holder().holder_constructed();
}

// Whether the class defines `method` itself, as pybind11 does (not a slot Python adds).
bool definesMethod(PyTypeObject* type, const char* method) {
  PyObject* attribute = PyDict_GetItemString(type->tp_dict, method);
  return attribute && PyInstanceMethod_Check(attribute);
}

bool isGuardedInstance(PyObject* object) {
  for (PyTypeObject* type : guardedTypes())
    if (PyObject_TypeCheck(object, type)) return true;
  return false;
}

// __init__ and __setstate__ of a class, called with args = (self, ...): refused when self is
// already initialised, else passed on to the class's own (`original`). m_self is the original.
PyObject* initialiseOnce(PyObject* original, PyObject* args, PyObject* kwargs) {
  PyObject* self = PyTuple_GET_SIZE(args) > 0 ? PyTuple_GET_ITEM(args, 0) : nullptr;
  if (self && isGuardedInstance(self) && initialised(self)) {
    const std::string name = publicName(Py_TYPE(self));
    PyErr_Format(PyExc_TypeError, "%s.%U: this object is already initialised; create a new one with %s(...)",
                 name.c_str(), py::getattr(original, "__name__").ptr(), name.c_str());
    return nullptr;
  }
  return PyObject_Call(original, args, kwargs);
}

// The wrapper keeps the original's name and docstring (its signatures); the definitions must
// live as long as the functions, which is the process.
void initialiseOnlyOnce(py::handle cls, const char* method) {
  if (!definesMethod(reinterpret_cast<PyTypeObject*>(cls.ptr()), method)) return;
  static std::deque<std::string> docs;
  static std::deque<PyMethodDef> definitions;
  py::object original = py::getattr(cls, method);
  docs.push_back(py::str(original.attr("__doc__")));
  definitions.push_back({method, reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&initialiseOnce)),
                         METH_VARARGS | METH_KEYWORDS, docs.back().c_str()});
  py::object function = py::reinterpret_steal<py::object>(PyCFunction_New(&definitions.back(), original.ptr()));
  if (!function) throw py::error_already_set();
  py::object bound = py::reinterpret_steal<py::object>(PyInstanceMethod_New(function.ptr()));
  if (!bound) throw py::error_already_set();
  py::setattr(cls, method, bound);
}

}  // namespace

void raiseNeverInitialised(PyTypeObject* type) {
  const std::string name = publicName(type);
  const bool constructible = definesMethod(type, "__init__");
  throw py::type_error("this " + name + " object was never initialised (made with __new__ alone): " +
                       (constructible ? "create it with " + name + "(...)"
                                      : name + " objects come from the module's functions, see help(" + name + ")"));
}

void guardClass(const std::type_info& type, void* (*refuseValue)(std::size_t)) {
  py::detail::type_info* info = py::detail::get_type_info(type);
  info->operator_new = refuseValue;
  guardedTypes().insert(info->type);
}

void requireInitialised(const py::handle& object) {
  if (isGuardedInstance(object.ptr()) && !initialised(object.ptr())) raiseNeverInitialised(Py_TYPE(object.ptr()));
}

void finishClasses(py::module_& m) {
  std::set<PyTypeObject*> finished;  // a class under a second name (TestSet) is wrapped once
  for (const auto& [name, value] : m.attr("__dict__").cast<py::dict>()) {
    if (!PyType_Check(value.ptr())) continue;
    auto* type = reinterpret_cast<PyTypeObject*>(value.ptr());
    if (!py::detail::get_type_info(type)) continue;  // not a pybind11 class
    if (!finished.insert(type).second) continue;
    if (!guardedTypes().count(type))
      throw std::logic_error("class " + publicName(type) + " was declared with py::class_, not boundClass");
    initialiseOnlyOnce(value, "__init__");
    initialiseOnlyOnce(value, "__setstate__");
  }
}

}  // namespace mdbrief::python
