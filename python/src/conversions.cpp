#include "conversions.hpp"

#include <filesystem>

namespace mdbrief::python {
namespace {

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

py::array asArray(const py::handle& object, const char* argument) {
  if (!py::isinstance<py::array>(object))
    throw py::type_error(std::string(argument) + " must be a numpy array, got " +
                         std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  return py::reinterpret_borrow<py::array>(object);
}

// dtype is checked first: a float image converted silently would describe other pixels.
py::array_t<uint8_t, py::array::c_style> uint8Array(const py::handle& object, const char* argument) {
  const py::array a = asArray(object, argument);
  if (!a.dtype().is(py::dtype::of<uint8_t>()))
    throw py::value_error(std::string(argument) + " must have dtype uint8, got " + std::string(py::str(a.dtype())));
  return py::array_t<uint8_t, py::array::c_style>::ensure(a);
}

// The module is kept for the life of the process: a static py::object would be released after
// the interpreter has shut down.
py::object cv2Attribute(const char* name) {
  static const py::handle cv2 = py::module_::import("cv2").release();
  return cv2.attr(name);
}

// cv2's binding keeps a cv2.KeyPoint's value right after the object header (OpenCV's
// generated `struct { PyObject_HEAD cv::KeyPoint v; }`). Reading it there skips six attribute
// lookups per keypoint, most of compute()'s binding overhead. Used only if a probe keypoint reads
// back exactly, so another cv2 layout falls back to the attributes.
PyTypeObject* keypointTypeWithKnownLayout() {
  static PyTypeObject* const type = [] () -> PyTypeObject* {
    const py::object make = cv2Attribute("KeyPoint");
    if (!PyType_Check(make.ptr())) return nullptr;
    auto* t = reinterpret_cast<PyTypeObject*>(make.ptr());
    if (t->tp_basicsize < static_cast<py::ssize_t>(sizeof(PyObject) + sizeof(cv::KeyPoint))) return nullptr;
    const cv::KeyPoint expected(1.5f, -2.25f, 31.f, 45.5f, 0.125f, 3, 7);
    const py::object probe = make(expected.pt.x, expected.pt.y, expected.size, expected.angle, expected.response,
                                  expected.octave, expected.class_id);
    if (Py_TYPE(probe.ptr()) != t) return nullptr;
    cv::KeyPoint got;
    std::memcpy(&got, reinterpret_cast<const char*>(probe.ptr()) + sizeof(PyObject), sizeof(cv::KeyPoint));
    const bool same = got.pt == expected.pt && got.size == expected.size && got.angle == expected.angle &&
                      got.response == expected.response && got.octave == expected.octave &&
                      got.class_id == expected.class_id;
    if (!same) return nullptr;
    make.inc_ref();  // the type stays alive with the module
    return t;
  }();
  return type;
}

}  // namespace

cv::Mat imageFromArray(const py::handle& object, const char* argument, py::object& keep, bool allowNone) {
  if (allowNone && object.is_none()) return {};
  auto a = uint8Array(object, argument);
  const bool grey = a.ndim() == 2;
  const bool colour = a.ndim() == 3 && (a.shape(2) == 3 || a.shape(2) == 4);
  if (!grey && !colour)
    throw py::value_error(std::string(argument) + " must have shape (H, W), (H, W, 3) or (H, W, 4), got " +
                          shapeText(a));
  if (a.size() == 0) {
    if (allowNone) return {};
    throw py::value_error(std::string(argument) + " is empty, shape " + shapeText(a));
  }
  keep = a;
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)),
                 CV_8UC(grey ? 1 : static_cast<int>(a.shape(2))), a.mutable_data());
}

cv::Mat descriptorsFromArray(const py::handle& object, const char* argument, py::object& keep) {
  auto a = uint8Array(object, argument);
  if (a.ndim() != 2) throw py::value_error(std::string(argument) + " must have shape (N, bytes), got " + shapeText(a));
  keep = a;
  if (a.shape(0) == 0) return cv::Mat(0, static_cast<int>(a.shape(1)), CV_8UC1);
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC1, a.mutable_data());
}

py::array_t<uint8_t> arrayFromMat(const cv::Mat& mat, int cols) {
  const py::ssize_t rows = mat.empty() ? 0 : mat.rows;
  py::array_t<uint8_t> out({rows, static_cast<py::ssize_t>(cols)});
  for (int r = 0; r < rows; ++r) std::memcpy(out.mutable_data(r, 0), mat.ptr(r), static_cast<size_t>(cols));
  return out;
}

py::array_t<double, py::array::c_style> pointsFromArray(const py::handle& object, int k, const char* argument,
                                                        bool& single) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  } catch (const py::error_already_set&) {
    throw py::type_error(std::string(argument) + " must be an array of numbers");
  }
  if (!a) throw py::type_error(std::string(argument) + " must be an array of numbers");
  single = a.ndim() == 1;
  if (!((a.ndim() == 2 && a.shape(1) == k) || (single && a.shape(0) == k)))
    throw py::value_error(std::string(argument) + " must have shape (N, " + std::to_string(k) + ") or (" +
                          std::to_string(k) + ",), got " + shapeText(a));
  return a;
}

std::vector<cv::KeyPoint> keypointsFromPython(const py::handle& sequence, const char* argument) {
  if (py::isinstance<py::str>(sequence) || !py::isinstance<py::sequence>(sequence))
    throw py::type_error(std::string(argument) + " must be a sequence of cv2.KeyPoint");
  // Attribute names made once: this loop is most of compute()'s binding overhead.
  static const py::handle names[] = {py::str("pt").release(),       py::str("size").release(),
                                     py::str("angle").release(),    py::str("response").release(),
                                     py::str("octave").release(),   py::str("class_id").release()};
  const auto items = py::reinterpret_borrow<py::sequence>(sequence);
  std::vector<cv::KeyPoint> out(items.size());
  PyTypeObject* const known = keypointTypeWithKnownLayout();
  for (size_t i = 0; i < out.size(); ++i) {
    const py::object k = items[i];
    if (known && Py_TYPE(k.ptr()) == known) {
      std::memcpy(&out[i], reinterpret_cast<const char*>(k.ptr()) + sizeof(PyObject), sizeof(cv::KeyPoint));
      continue;
    }
    double values[7];
    bool ok = true;
    for (int a = 0; a < 6 && ok; ++a) {
      const py::object v = py::reinterpret_steal<py::object>(PyObject_GetAttr(k.ptr(), names[a].ptr()));
      if (!v) {
        ok = false;
      } else if (a == 0) {
        ok = PyTuple_Check(v.ptr()) && PyTuple_GET_SIZE(v.ptr()) == 2;
        for (int c = 0; c < 2 && ok; ++c) values[c] = PyFloat_AsDouble(PyTuple_GET_ITEM(v.ptr(), c));
      } else {
        values[a + 1] = a < 4 ? PyFloat_AsDouble(v.ptr()) : static_cast<double>(PyLong_AsLong(v.ptr()));
      }
    }
    if (!ok || PyErr_Occurred()) {
      PyErr_Clear();
      throw py::type_error(std::string(argument) + "[" + std::to_string(i) + "] is not a cv2.KeyPoint");
    }
    out[i] = cv::KeyPoint(static_cast<float>(values[0]), static_cast<float>(values[1]), static_cast<float>(values[2]),
                          static_cast<float>(values[3]), static_cast<float>(values[4]), static_cast<int>(values[5]),
                          static_cast<int>(values[6]));
  }
  return out;
}

py::list keypointsToPython(const std::vector<cv::KeyPoint>& keypoints) {
  // A direct vectorcall of the cv2.KeyPoint type: most of detect_and_compute()'s binding overhead
  // is making these objects.
  const py::object make = cv2Attribute("KeyPoint");
  py::list out(keypoints.size());
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    const py::object args[] = {py::reinterpret_steal<py::object>(PyFloat_FromDouble(k.pt.x)),
                               py::reinterpret_steal<py::object>(PyFloat_FromDouble(k.pt.y)),
                               py::reinterpret_steal<py::object>(PyFloat_FromDouble(k.size)),
                               py::reinterpret_steal<py::object>(PyFloat_FromDouble(k.angle)),
                               py::reinterpret_steal<py::object>(PyFloat_FromDouble(k.response)),
                               py::reinterpret_steal<py::object>(PyLong_FromLong(k.octave)),
                               py::reinterpret_steal<py::object>(PyLong_FromLong(k.class_id))};
    PyObject* raw[7];
    for (int a = 0; a < 7; ++a) {
      if (!args[a]) throw py::error_already_set();
      raw[a] = args[a].ptr();
    }
    PyObject* keypoint = PyObject_Vectorcall(make.ptr(), raw, 7, nullptr);
    if (!keypoint) throw py::error_already_set();
    PyList_SET_ITEM(out.ptr(), static_cast<py::ssize_t>(i), keypoint);
  }
  return out;
}

py::list matchesToPython(const std::vector<cv::DMatch>& matches) {
  const py::object make = cv2Attribute("DMatch");
  py::list out(matches.size());
  for (size_t i = 0; i < matches.size(); ++i)
    out[i] = make(matches[i].queryIdx, matches[i].trainIdx, matches[i].distance);  // cv2's fastest overload
  return out;
}

py::array matchesToArray(const std::vector<cv::DMatch>& matches) {
  struct Row {
    int32_t query, train;
    float distance;
  };
  // Kept for the life of the process, like the cv2 module above.
  static const py::handle type = [] {
    py::list names, formats, offsets;
    names.append("query_idx"), names.append("train_idx"), names.append("distance");
    formats.append("<i4"), formats.append("<i4"), formats.append("<f4");
    offsets.append(offsetof(Row, query)), offsets.append(offsetof(Row, train)), offsets.append(offsetof(Row, distance));
    py::dict spec;
    spec["names"] = names, spec["formats"] = formats, spec["offsets"] = offsets, spec["itemsize"] = sizeof(Row);
    return py::dtype::from_args(spec).release();
  }();
  py::array out(py::reinterpret_borrow<py::dtype>(type), std::vector<py::ssize_t>{static_cast<py::ssize_t>(matches.size())},
                std::vector<py::ssize_t>{static_cast<py::ssize_t>(sizeof(Row))});
  auto* rows = static_cast<Row*>(out.mutable_data());
  for (size_t i = 0; i < matches.size(); ++i) rows[i] = {matches[i].queryIdx, matches[i].trainIdx, matches[i].distance};
  return out;
}

void requireFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    PyErr_SetObject(PyExc_FileNotFoundError,
                    py::make_tuple(2, "No such file or directory", path).ptr());
    throw py::error_already_set();
  }
}

}  // namespace mdbrief::python
