#pragma once
// Direct access to the C++ value inside cv2.KeyPoint and cv2.DMatch objects. cv2's generated
// binding stores such a value right after the object header (`struct { PyObject_HEAD T v; }`), so
// it can be read, and a new object made, without a Python call per field: most of the binding's
// cost for 1000 keypoints or matches. Each type is probed once (a value made by cv2's constructor
// is read back, and a value written here is read back through cv2's attributes); if cv2's layout
// differs, type() is null and callers use the attributes and constructors instead.
#include <opencv2/core.hpp>
#include <pybind11/pybind11.h>

namespace mdbrief::python {

template <typename T>
struct Cv2Value {
  // cv2's type object when its layout was confirmed, else nullptr.
  static PyTypeObject* type();
  // The value of an object of exactly type() (the caller checks Py_TYPE).
  static T read(PyObject* object);
  // A new reference to a new object of type() holding `value`, or null with a Python error set.
  static PyObject* make(const T& value);
};

// The attribute paths, for objects of any other type (and for the probes).
cv::KeyPoint keypointFromAttributes(PyObject* object, bool& ok);
cv::DMatch matchFromAttributes(PyObject* object, bool& ok);

}  // namespace mdbrief::python
