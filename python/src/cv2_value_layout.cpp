#include "cv2_value_layout.hpp"

#include <climits>
#include <cstring>
#include <new>

namespace mdbrief::python {

namespace py = pybind11;

namespace {

// Kept for the life of the process (a static py::object would be released after the interpreter).
PyObject* cv2Type(const char* name) {
  static const py::handle cv2 = py::module_::import("cv2").release();
  return py::object(cv2.attr(name)).release().ptr();
}

bool same(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  return a.pt == b.pt && a.size == b.size && a.angle == b.angle && a.response == b.response &&
         a.octave == b.octave && a.class_id == b.class_id;
}
bool same(const cv::DMatch& a, const cv::DMatch& b) {
  return a.queryIdx == b.queryIdx && a.trainIdx == b.trainIdx && a.imgIdx == b.imgIdx && a.distance == b.distance;
}

cv::KeyPoint fromAttributes(PyObject* o, bool& ok, cv::KeyPoint*) { return keypointFromAttributes(o, ok); }
cv::DMatch fromAttributes(PyObject* o, bool& ok, cv::DMatch*) { return matchFromAttributes(o, ok); }

const char* cv2Name(cv::KeyPoint*) { return "KeyPoint"; }
const char* cv2Name(cv::DMatch*) { return "DMatch"; }

py::object construct(PyObject* type, const cv::KeyPoint& k) {
  return py::reinterpret_borrow<py::object>(type)(k.pt.x, k.pt.y, k.size, k.angle, k.response, k.octave,
                                                  k.class_id);
}
py::object construct(PyObject* type, const cv::DMatch& m) {
  return py::reinterpret_borrow<py::object>(type)(m.queryIdx, m.trainIdx, m.imgIdx, m.distance);
}

// Values no default-constructed object holds, exactly representable.
cv::KeyPoint probeValue(cv::KeyPoint*) { return {1.5f, -2.25f, 31.f, 45.5f, 0.125f, 3, 7}; }
cv::DMatch probeValue(cv::DMatch*) { return {11, 22, 3, 4.75f}; }

template <typename T>
PyTypeObject* probedType() {
  // A signal that arrived during the caller's native work (Ctrl-C during the first match) is
  // handled first, raising KeyboardInterrupt: cv2's constructor crashed when called with one
  // pending. The probe runs again on the next call.
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  PyObject* object = cv2Type(cv2Name(static_cast<T*>(nullptr)));
  if (!PyType_Check(object)) return nullptr;
  auto* type = reinterpret_cast<PyTypeObject*>(object);
  if (type->tp_basicsize < static_cast<py::ssize_t>(sizeof(PyObject) + sizeof(T)) || !type->tp_alloc) return nullptr;
  const T expected = probeValue(static_cast<T*>(nullptr));
  // cv2 -> here.
  const py::object made = construct(object, expected);
  if (Py_TYPE(made.ptr()) != type || !same(Cv2Value<T>::read(made.ptr()), expected)) return nullptr;
  // Here -> cv2.
  PyObject* raw = type->tp_alloc(type, 0);
  if (!raw) throw py::error_already_set();
  const py::object written = py::reinterpret_steal<py::object>(raw);
  new (reinterpret_cast<char*>(raw) + sizeof(PyObject)) T(expected);
  bool ok = true;
  const T back = fromAttributes(raw, ok, static_cast<T*>(nullptr));
  if (!ok || !same(back, expected)) {
    PyErr_Clear();
    return nullptr;
  }
  return type;
}

// Number attribute `name` of o; ok turns false on the first failure, with the Python error set.
double floatAttribute(PyObject* o, const char* name, bool& ok) {
  PyObject* v = ok ? PyObject_GetAttrString(o, name) : nullptr;
  if (!v) return ok = false, 0.0;
  const double r = PyFloat_AsDouble(v);
  Py_DECREF(v);
  if (PyErr_Occurred()) ok = false;
  return r;
}

// Int attribute `name` of o (a float is refused with TypeError). A value outside the C int range
// is an OverflowError naming the attribute and the value: a cast would wrap 2**32 + 3 to 3.
int intAttribute(PyObject* o, const char* name, bool& ok) {
  PyObject* v = ok ? PyObject_GetAttrString(o, name) : nullptr;
  if (!v) return ok = false, 0;
  int overflow = 0;
  const long r = PyLong_AsLongAndOverflow(v, &overflow);
  if (!PyErr_Occurred() && (overflow != 0 || r < INT_MIN || r > INT_MAX))
    PyErr_Format(PyExc_OverflowError, "%s = %R is outside the range of a C int", name, v);
  Py_DECREF(v);
  if (PyErr_Occurred()) ok = false;
  return static_cast<int>(r);
}

}  // namespace

template <typename T>
PyTypeObject* Cv2Value<T>::type() {
  static PyTypeObject* const t = probedType<T>();
  return t;
}

template <typename T>
T Cv2Value<T>::read(PyObject* object) {
  T value;
  std::memcpy(static_cast<void*>(&value), reinterpret_cast<const char*>(object) + sizeof(PyObject), sizeof(T));
  return value;
}

template <typename T>
PyObject* Cv2Value<T>::make(const T& value) {
  PyTypeObject* t = type();
  PyObject* object = t->tp_alloc(t, 0);
  if (object) new (reinterpret_cast<char*>(object) + sizeof(PyObject)) T(value);
  return object;
}

template struct Cv2Value<cv::KeyPoint>;
template struct Cv2Value<cv::DMatch>;

cv::KeyPoint keypointFromAttributes(PyObject* o, bool& ok) {
  cv::KeyPoint k;
  PyObject* pt = PyObject_GetAttrString(o, "pt");
  if (!pt || !PyTuple_Check(pt) || PyTuple_GET_SIZE(pt) != 2) {
    Py_XDECREF(pt);
    ok = false;
    return k;
  }
  k.pt.x = static_cast<float>(PyFloat_AsDouble(PyTuple_GET_ITEM(pt, 0)));
  k.pt.y = static_cast<float>(PyFloat_AsDouble(PyTuple_GET_ITEM(pt, 1)));
  Py_DECREF(pt);
  k.size = static_cast<float>(floatAttribute(o, "size", ok));
  k.angle = static_cast<float>(floatAttribute(o, "angle", ok));
  k.response = static_cast<float>(floatAttribute(o, "response", ok));
  k.octave = intAttribute(o, "octave", ok);
  k.class_id = intAttribute(o, "class_id", ok);
  if (PyErr_Occurred()) ok = false;
  return k;
}

cv::DMatch matchFromAttributes(PyObject* o, bool& ok) {
  cv::DMatch m;
  m.queryIdx = intAttribute(o, "queryIdx", ok);
  m.trainIdx = intAttribute(o, "trainIdx", ok);
  m.imgIdx = intAttribute(o, "imgIdx", ok);
  m.distance = static_cast<float>(floatAttribute(o, "distance", ok));
  return m;
}

}  // namespace mdbrief::python
