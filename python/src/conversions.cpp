#include "conversions.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <thread>

#include "cv2_value_layout.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"

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

// cv::Mat has no read-only form; the library only reads its inputs, so a read-only array's
// memory is shared as it is.
uint8_t* sharedData(const py::array_t<uint8_t, py::array::c_style>& a) { return const_cast<uint8_t*>(a.data()); }

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

// The items of a sequence of cv2 values (or of objects with their attributes); an item that is
// neither, or whose field overflows, is named as argument[i].
template <typename T>
std::vector<T> cv2Values(const py::sequence& items, const char* argument, const char* typeName,
                         T (*fromAttributes)(PyObject*, bool&)) {
  PyTypeObject* const cv2Type = Cv2Value<T>::type();
  std::vector<T> out(items.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const py::object item = items[i];
    bool ok = true;
    out[i] = cv2Type && Py_TYPE(item.ptr()) == cv2Type ? Cv2Value<T>::read(item.ptr()) : fromAttributes(item.ptr(), ok);
    if (!ok) {
      const std::string where = std::string(argument) + "[" + std::to_string(i) + "]";
      if (PyErr_ExceptionMatches(PyExc_OverflowError)) {
        const py::error_already_set range;
        throw py::value_error(where + "." + std::string(py::str(range.value())));
      }
      PyErr_Clear();
      throw py::type_error(where + " is not a " + typeName);
    }
  }
  return out;
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
                 CV_8UC(grey ? 1 : static_cast<int>(a.shape(2))), sharedData(a));
}

cv::Mat descriptorsFromArray(const py::handle& object, const char* argument, py::object& keep) {
  auto a = uint8Array(object, argument);
  if (a.ndim() != 2) throw py::value_error(std::string(argument) + " must have shape (N, bytes), got " + shapeText(a));
  keep = a;
  if (a.shape(0) == 0) return cv::Mat(0, static_cast<int>(a.shape(1)), CV_8UC1);
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_8UC1, sharedData(a));
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
    // numpy casts True to 1.0: a boolean array (a mask passed by mistake) would pass as points.
    const py::array any = py::array::ensure(object);
    if (any && any.dtype().kind() == 'b')
      throw py::type_error(std::string(argument) + " must be an array of numbers, got booleans");
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

int saturatedInt(const py::int_& value) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
  if (overflow != 0) return overflow > 0 ? INT_MAX : INT_MIN;
  return static_cast<int>(std::clamp<long long>(v, INT_MIN, INT_MAX));
}

std::vector<cv::KeyPoint> keypointsFromPython(const py::handle& sequence, const char* argument) {
  if (py::isinstance<py::str>(sequence) || !py::isinstance<py::sequence>(sequence))
    throw py::type_error(std::string(argument) + " must be a sequence of cv2.KeyPoint");
  return cv2Values<cv::KeyPoint>(py::reinterpret_borrow<py::sequence>(sequence), argument, "cv2.KeyPoint",
                                 keypointFromAttributes);
}

py::list keypointsToPython(const std::vector<cv::KeyPoint>& keypoints) {
  const bool direct = Cv2Value<cv::KeyPoint>::type() != nullptr;
  const py::object make = cv2Attribute("KeyPoint");
  py::list out(keypoints.size());
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    PyObject* keypoint = direct ? Cv2Value<cv::KeyPoint>::make(k)
                                : make(k.pt.x, k.pt.y, k.size, k.angle, k.response, k.octave, k.class_id).release().ptr();
    if (!keypoint) throw py::error_already_set();
    PyList_SET_ITEM(out.ptr(), static_cast<py::ssize_t>(i), keypoint);
  }
  return out;
}

py::list matchesToPython(const std::vector<cv::DMatch>& matches) {
  const bool direct = Cv2Value<cv::DMatch>::type() != nullptr;
  const py::object make = cv2Attribute("DMatch");
  py::list out(matches.size());
  for (size_t i = 0; i < matches.size(); ++i) {
    const cv::DMatch& m = matches[i];
    PyObject* match = direct ? Cv2Value<cv::DMatch>::make(m) : make(m.queryIdx, m.trainIdx, m.distance).release().ptr();
    if (!match) throw py::error_already_set();
    PyList_SET_ITEM(out.ptr(), static_cast<py::ssize_t>(i), match);
  }
  return out;
}

namespace {

// One integer field of a structured match array, as int64.
using Int64Column = py::array_t<long long, py::array::c_style | py::array::forcecast>;

Int64Column matchField(const py::array& rows, const char* field, const char* argument) {
  const py::array column = rows[py::str(field)];
  const char kind = column.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw py::type_error(std::string(argument) + "['" + field + "'] must hold integers, got dtype " +
                         std::string(py::str(column.dtype())));
  Int64Column out = Int64Column::ensure(column);
  if (!out) throw py::type_error(std::string(argument) + "['" + field + "'] must hold integers");
  return out;
}

std::vector<cv::DMatch> matchesFromArray(const py::array& rows, const char* argument) {
  const py::object names = rows.dtype().attr("names");
  const auto has = [&](const char* field) { return !names.is_none() && names.contains(field); };
  if (!has("query_idx") || !has("train_idx") || rows.ndim() != 1)
    throw py::value_error(std::string(argument) + " must be a sequence of cv2.DMatch or a 1-D structured array with "
                          "fields query_idx and train_idx (mdbrief.match(..., as_array=True)), got an array of dtype " +
                          std::string(py::str(rows.dtype())) + " and shape " + shapeText(rows));
  const auto query = matchField(rows, "query_idx", argument), train = matchField(rows, "train_idx", argument);
  std::vector<cv::DMatch> out(static_cast<size_t>(rows.shape(0)));
  for (size_t i = 0; i < out.size(); ++i) {
    for (const auto& [value, field] : {std::pair(query.data()[i], "query_idx"), std::pair(train.data()[i], "train_idx")})
      if (value < INT_MIN || value > INT_MAX)
        throw py::value_error(std::string(argument) + "[" + std::to_string(i) + "]." + field + " = " +
                              std::to_string(value) + " is outside the range of a C int");
    out[i] = cv::DMatch(static_cast<int>(query.data()[i]), static_cast<int>(train.data()[i]), 0.f);
  }
  return out;
}

}  // namespace

std::vector<cv::DMatch> matchesFromPython(const py::handle& object, const char* argument) {
  if (py::isinstance<py::array>(object)) return matchesFromArray(py::reinterpret_borrow<py::array>(object), argument);
  if (py::isinstance<py::str>(object) || !py::isinstance<py::sequence>(object))
    throw py::type_error(std::string(argument) + " must be a sequence of cv2.DMatch or mdbrief.match's structured array");
  return cv2Values<cv::DMatch>(py::reinterpret_borrow<py::sequence>(object), argument, "cv2.DMatch",
                               matchFromAttributes);
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

bool isPath(const py::handle& object) {
  static const py::handle pathLike = py::object(py::module_::import("os").attr("PathLike")).release();
  return py::isinstance<py::str>(object) || py::isinstance<py::bytes>(object) || py::isinstance(object, pathLike);
}

std::string pathFrom(const py::handle& object, const char* argument) {
  static const py::handle fsencode = py::object(py::module_::import("os").attr("fsencode")).release();
  if (!isPath(object))
    throw py::type_error(std::string(argument) + " must be a path (str, bytes or os.PathLike), got " +
                         std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  std::string path = py::bytes(fsencode(object));
  if (path.find('\0') != std::string::npos)
    throw py::value_error(std::string(argument) + " holds a NUL byte, which no file name can hold");
  return path;
}

py::str pathText(const std::string& path) {
  PyObject* text = PyUnicode_DecodeFSDefaultAndSize(path.data(), static_cast<py::ssize_t>(path.size()));
  if (!text) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(text);
}

void raiseFileNotFound(const std::string& path, const char* reason) {
  PyErr_SetObject(PyExc_FileNotFoundError, py::make_tuple(2, reason, pathText(path)).ptr());
  throw py::error_already_set();
}

void requireFile(const std::string& path) {
  const std::string problem = internal::inputFileProblem(path);
  if (problem.empty()) return;
  // OSError(errno, text, path) becomes the subclass open() would raise: FileNotFoundError,
  // IsADirectoryError, PermissionError; a FIFO or a device is a plain OSError.
  struct stat info {};
  const int error = ::stat(path.c_str(), &info) != 0 ? errno : S_ISDIR(info.st_mode) ? EISDIR : EINVAL;
  PyErr_SetObject(PyExc_OSError, py::make_tuple(error, problem, pathText(path)).ptr());
  throw py::error_already_set();
}

std::function<void()> pythonSignalCheck() {
  return [caller = std::this_thread::get_id()] {
    if (std::this_thread::get_id() != caller) return;
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw PythonSignalRaised();
  };
}

}  // namespace mdbrief::python
