#pragma once
// Conversions between numpy / cv2 objects and the C++ types of libmdbrief. Every check raises
// ValueError (or TypeError for a wrong kind of object) naming the argument, before any C++ code
// runs on the data.
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace mdbrief::python {

namespace py = pybind11;

// A uint8 image, (H, W) grey or (H, W, 3|4) BGR(A), as a cv::Mat that shares the array's memory
// (the array is made C-contiguous first if it is not; `keep` holds it alive). Read-only arrays
// are taken as they are: the library never writes its inputs. None or an empty array only where
// `allowNone` (then an empty Mat).
cv::Mat imageFromArray(const py::handle& object, const char* argument, py::object& keep, bool allowNone = false);

// (N, bytes) uint8 descriptors or masks, as a cv::Mat sharing the memory (`keep` holds it;
// read-only arrays too, as for images).
cv::Mat descriptorsFromArray(const py::handle& object, const char* argument, py::object& keep);

// A copy of a CV_8UC1 matrix as an (N, cols) uint8 array; an empty matrix gives shape (0, cols).
py::array_t<uint8_t> arrayFromMat(const cv::Mat& mat, int cols);

// (N, k) float64 points: accepts any array-like of numbers of shape (N, k), or (k,) for a single
// point (then `single` is set); booleans are refused (TypeError).
py::array_t<double, py::array::c_style> pointsFromArray(const py::handle& object, int k, const char* argument,
                                                        bool& single);

// cv2.KeyPoint objects (anything with pt, size, angle, response, octave, class_id) and back. An
// octave or class_id outside the C int range raises ValueError naming the keypoint.
// A Python int as a C int, saturated at INT_MIN and INT_MAX: a huge value reaches the caller's
// range check (ValueError) or means "all", instead of pybind11's "incompatible function
// arguments".
int saturatedInt(const py::int_& value);

std::vector<cv::KeyPoint> keypointsFromPython(const py::handle& sequence, const char* argument);
py::list keypointsToPython(const std::vector<cv::KeyPoint>& keypoints);
py::list matchesToPython(const std::vector<cv::DMatch>& matches);
// Matches as mdbrief.match gives them: cv2.DMatch objects (anything with queryIdx, trainIdx,
// imgIdx and distance), or its structured array (fields query_idx and train_idx; a distance is
// not read from it). An index outside the C int range raises ValueError naming the match; the
// indices are not checked against any keypoints here.
std::vector<cv::DMatch> matchesFromPython(const py::handle& object, const char* argument);
// The same as a structured array: query_idx, train_idx (int32), distance (float32).
py::array matchesToArray(const std::vector<cv::DMatch>& matches);

// A path argument (str, bytes or os.PathLike) as the file system's bytes (os.fsencode). Raises
// TypeError for anything else and ValueError for a path holding a NUL byte, which the C++ side
// would cut there.
std::string pathFrom(const py::handle& object, const char* argument);
// Whether pathFrom takes `object` as one path (not as a sequence of them).
bool isPath(const py::handle& object);
// A path back as str, decoded as the file system spells it (os.fsdecode): any bytes decode.
py::str pathText(const std::string& path);

// Raises OSError naming the path (as pathText gives it) and the reason unless it is an existing
// regular file: FileNotFoundError when nothing is there, IsADirectoryError for a folder.
void requireFile(const std::string& path);
// Raises FileNotFoundError (`reason`, with the path as pathText gives it as its filename).
[[noreturn]] void raiseFileNotFound(const std::string& path, const char* reason);

// Thrown by checkPythonSignals when a Python signal handler raised (KeyboardInterrupt); the
// Python error stays set for the caller to raise (py::error_already_set).
struct PythonSignalRaised : std::exception {
  const char* what() const noexcept override { return "a Python signal handler raised"; }
};

// A check for long computations that released the GIL: on the thread that made it (only that
// thread can run Python's signal handlers), takes the GIL and runs them, throwing
// PythonSignalRaised when one raised; does nothing on other threads.
std::function<void()> pythonSignalCheck();

}  // namespace mdbrief::python
