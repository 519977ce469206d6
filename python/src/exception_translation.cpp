// C++ exceptions as Python exceptions whose message survives any bytes. pybind11 sets messages
// with PyErr_SetString, which decodes them as strict UTF-8: a message quoting a file's invalid
// bytes (a camera key \xff\xfe, a UTF-16 JSON file) became an exception with no message at all.
#include <cstring>

#include "bindings.hpp"

namespace mdbrief::python {
namespace {

void raise(PyObject* type, const char* message) {
  PyObject* text = PyUnicode_DecodeUTF8(message, static_cast<py::ssize_t>(std::strlen(message)), "backslashreplace");
  if (!text) return;  // the decoding error (MemoryError) stays set
  PyErr_SetObject(type, text);
  Py_DECREF(text);
}

// pybind11's own mapping of exception types, with the message decoded leniently; other
// exceptions go on to pybind11's translators.
void translate(std::exception_ptr exception) {
  try {
    std::rethrow_exception(exception);
  } catch (const py::builtin_exception& e) {
    // The Python type is whatever set_error() raises; its message is replaced.
    e.set_error();
    PyObject *type, *value, *traceback;
    PyErr_Fetch(&type, &value, &traceback);
    Py_XDECREF(value);
    Py_XDECREF(traceback);
    raise(type, e.what());
    Py_XDECREF(type);
  } catch (const std::domain_error& e) {
    raise(PyExc_ValueError, e.what());
  } catch (const std::invalid_argument& e) {
    raise(PyExc_ValueError, e.what());
  } catch (const std::length_error& e) {
    raise(PyExc_ValueError, e.what());
  } catch (const std::out_of_range& e) {
    raise(PyExc_IndexError, e.what());
  } catch (const std::range_error& e) {
    raise(PyExc_ValueError, e.what());
  } catch (const std::overflow_error& e) {
    raise(PyExc_OverflowError, e.what());
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    raise(PyExc_RuntimeError, e.what());
  }
}

}  // namespace

void translateExceptions() { py::register_local_exception_translator(&translate); }

}  // namespace mdbrief::python
