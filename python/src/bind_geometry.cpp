// mdbrief.fit_essential, fit_homography, check_known_pose: two-view geometry on matched bearing
// vectors (mdbrief/geometry/two_view.hpp), each giving a TwoViewResult; mdbrief.pixels_per_radian
// for thresholds in pixels.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera/camera.hpp"
#include "mdbrief/geometry/two_view.hpp"
#include "option_keywords.hpp"

namespace mdbrief::python {
namespace {

// What Python sees of a fit: the C++ result and which model it is.
struct PyTwoViewResult {
  std::string kind;  // "essential", "homography", "known pose"
  TwoViewResult result;
  std::optional<cv::Matx33d> model;  // E or H; none for the known pose (the caller's)
  std::optional<RelativePose> pose;
};

py::array matrixArray(const cv::Matx33d& m) {
  py::array_t<double> out({3, 3});
  auto v = out.mutable_unchecked<2>();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v(i, j) = m(i, j);
  return std::move(out);
}

// A ray whose length overflows or underflows (1e200, 1e-170) scaled to a largest component of 1,
// which keeps its direction: the library normalises by the length. Others are unchanged, so the
// library sees what it always saw. False for a ray with no direction (not finite, or zero).
bool directionKept(cv::Vec3d& v) {
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) return false;
  const double length = cv::norm(v);
  if (length > 0 && std::isfinite(length)) return true;
  const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(largest > 0)) return false;
  v = cv::Vec3d(v[0] / largest, v[1] / largest, v[2] / largest);
  return true;
}

// An (N, 3) array of bearings: finite, non-zero rows (any length: the library normalises).
std::vector<cv::Vec3d> bearingsFrom(const py::handle& object, const char* argument, const char* callable) {
  bool single = false;
  const auto a = pointsFromArray(object, 3, argument, single);
  if (single)
    throw py::value_error(std::string(argument) + " must have shape (N, 3), got (3,): one bearing per row");
  std::vector<cv::Vec3d> out(a.shape(0));
  const double* p = a.data();
  for (size_t k = 0; k < out.size(); ++k) {
    out[k] = cv::Vec3d(p[3 * k], p[3 * k + 1], p[3 * k + 2]);
    if (!directionKept(out[k]))
      throw py::value_error(std::string(callable) + ": " + argument + "[" + std::to_string(k) +
                            "] must be finite and non-zero");
  }
  return out;
}

// The library's messages name its C++ function and parameters (checkKnownPose: pose.rotation);
// Python users called `callable` with bearings_a, bearings_b, rotation and translation.
[[noreturn]] void raiseInPythonNames(const std::invalid_argument& e, const char* function, const char* callable) {
  std::string message = e.what();
  const auto replace = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
  };
  replace(std::string(function) + ":", std::string(callable) + ":");
  replace("pose.rotation", "rotation");
  replace("pose.translation", "translation");
  replace("bearing a[", "bearings_a[");
  replace("bearing b[", "bearings_b[");
  replace("pixelsPerRadian", "pixels_per_radian");
  throw py::value_error(message);
}

// None, or one positive value per match.
std::vector<double> scalesFrom(const py::handle& object, size_t matches) {
  if (object.is_none()) return {};
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  } catch (const py::error_already_set&) {
    throw py::type_error("pixels_per_radian must be an array of numbers or None");
  }
  if (!a || a.ndim() != 1 || static_cast<size_t>(a.shape(0)) != matches)
    throw py::value_error("pixels_per_radian must have shape (" + std::to_string(matches) + ",): one per match");
  std::vector<double> out(a.data(), a.data() + matches);
  for (size_t k = 0; k < matches; ++k)
    if (!(out[k] > 0) || !std::isfinite(out[k]))
      throw py::value_error("pixels_per_radian[" + std::to_string(k) + "] must be positive and finite");
  return out;
}

struct Inputs {
  std::vector<cv::Vec3d> a, b;
  std::vector<double> scale;
  TwoViewOptions options;
};

Inputs inputsFrom(const py::handle& bearingsA, const py::handle& bearingsB, const py::handle& pixelsPerRadian,
                  const py::kwargs& kwargs, const char* callable) {
  Inputs in;
  in.a = bearingsFrom(bearingsA, "bearings_a", callable);
  in.b = bearingsFrom(bearingsB, "bearings_b", callable);
  if (in.a.size() != in.b.size())
    throw py::value_error("bearings_a has " + std::to_string(in.a.size()) + " rows and bearings_b " +
                          std::to_string(in.b.size()) + ": one row each per match");
  in.scale = scalesFrom(pixelsPerRadian, in.a.size());
  in.options = optionsFromKeywords(twoViewOptionFields(), kwargs, callable,
                                   [](const TwoViewOptions& o) { validate(o); });
  return in;
}

cv::Matx33d matrixFrom(const py::handle& object, const char* argument) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  } catch (const py::error_already_set&) {
    throw py::type_error(std::string(argument) + " must be a 3x3 array of numbers");
  }
  if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
    throw py::value_error(std::string(argument) + " must have shape (3, 3)");
  cv::Matx33d m;
  for (int i = 0; i < 9; ++i) m.val[i] = a.data()[i];
  return m;
}

cv::Vec3d vectorFrom(const py::handle& object, const char* argument) {
  bool single = false;
  const auto a = pointsFromArray(object, 3, argument, single);
  if (!single && !(a.ndim() == 2 && a.shape(0) == 1))
    throw py::value_error(std::string(argument) + " must have shape (3,)");
  return {a.data()[0], a.data()[1], a.data()[2]};
}

const char* const kOptionsDoc = R"doc(
Options (keywords; mdbrief.option_fields("two_view") lists them with their ranges):
max_angle (0.005 rad), or max_pixels (2.0) when pixels_per_radian is given; confidence (0.999),
max_iterations (3000), seed (1), refine (True), in_front (True), max_false_alarms (0.01: a fit
fails with "inliers no more than chance" when random matches would give a model as good in 1 fit
of 100 or more).)doc";

}  // namespace

void bindGeometry(py::module_& m) {
  boundClass<PyTwoViewResult>(m, "TwoViewResult", R"doc(
A two-view fit or check of matched bearings: per match, the inlier flag and the residual (an
angle, radians); the model. When the fit fails, ok is False, reason says why ("too few matches",
"all matches on the same point", "all matches on a line", "no model found", "inliers no more than
chance"), no match is an inlier and residuals is empty.)doc")
      .def_property_readonly("kind", [](const PyTwoViewResult& r) { return r.kind; },
                             "'essential', 'homography' or 'known pose'.")
      .def_property_readonly("ok", [](const PyTwoViewResult& r) { return r.result.ok(); })
      .def_property_readonly("reason", [](const PyTwoViewResult& r) { return r.result.reason; },
                             "Empty when ok, else why no model was found.")
      .def_property_readonly(
          "inliers",
          [](const PyTwoViewResult& r) {
            py::array_t<bool> out(static_cast<py::ssize_t>(r.result.inliers.size()));
            bool* p = out.mutable_data();
            for (size_t k = 0; k < r.result.inliers.size(); ++k) p[k] = r.result.inliers[k] != 0;
            return out;
          },
          "(N,) bool: the matches the model explains.")
      .def_property_readonly(
          "residuals",
          [](const PyTwoViewResult& r) {
            return py::array_t<double>(static_cast<py::ssize_t>(r.result.residuals.size()), r.result.residuals.data());
          },
          "(N,) float64, radians: the epipolar angle (essential, known pose) or the angle between b and\n"
          "H a (homography). Empty when the fit failed.")
      .def_property_readonly("inlier_count", [](const PyTwoViewResult& r) { return r.result.inlierCount; })
      .def_property_readonly(
          "log10_false_alarms", [](const PyTwoViewResult& r) { return r.result.log10FalseAlarms; },
          "Fits: log10 of the model's number of false alarms, how many models as good random matches\n"
          "would give (max_false_alarms); also when the fit failed on it. 0 for a known pose.")
      .def_property_readonly(
          "model",
          [](const PyTwoViewResult& r) -> py::object {
            if (!r.model || !r.result.ok()) return py::none();
            return matrixArray(*r.model);
          },
          "3x3: the essential matrix E = [t]x R (a . E b = 0) or the homography H (b ~ H a); None for\n"
          "the known pose and for a failed fit.")
      .def_property_readonly(
          "rotation",
          [](const PyTwoViewResult& r) -> py::object {
            if (!r.pose || !r.result.ok()) return py::none();
            return matrixArray(r.pose->rotation);
          },
          "3x3 R of the pose of camera b in camera a's frame (X_a = R X_b + t); None without a pose.")
      .def_property_readonly(
          "translation",
          [](const PyTwoViewResult& r) -> py::object {
            if (!r.pose || !r.result.ok()) return py::none();
            py::array_t<double> t(3);
            for (int i = 0; i < 3; ++i) t.mutable_data()[i] = r.pose->translation[i];
            return std::move(t);
          },
          "(3,) t of that pose (unit length for a fit); None without a pose.")
      .def("__repr__", [](const PyTwoViewResult& r) {
             if (!r.result.ok()) return "<mdbrief.TwoViewResult " + r.kind + ": " + r.result.reason + ">";
             return "<mdbrief.TwoViewResult " + r.kind + ": " + std::to_string(r.result.inlierCount) + " of " +
                    std::to_string(r.result.inliers.size()) + " inliers>";
           });

  m.def(
      "fit_essential",
      [](const py::handle& a, const py::handle& b, const py::handle& scale, const py::kwargs& kwargs) {
        const Inputs in = inputsFrom(a, b, scale, kwargs, "fit_essential");
        PyTwoViewResult out;
        out.kind = "essential";
        try {
          TwoViewOptions options = in.options;
          options.interruptCheck = pythonSignalCheck();
          py::gil_scoped_release release;
          EssentialResult fit = fitEssential(in.a, in.b, options, in.scale);
          out.model = fit.essential;
          out.pose = fit.pose;
          out.result = std::move(fit);
        } catch (const PythonSignalRaised&) {
          throw py::error_already_set();
        } catch (const std::invalid_argument& e) {
          raiseInPythonNames(e, "fitEssential", "fit_essential");
        }
        return out;
      },
      py::arg("bearings_a"), py::arg("bearings_b"), py::kw_only(), py::arg("pixels_per_radian") = py::none(),
      (std::string(R"doc(
Relative pose of a general scene from matched bearings (Nx3 rows, Camera.pixel_to_bearing of each
image: any lens, beyond 90 degrees of incidence): RANSAC over the 5-point solver, the pose that
puts the inliers in front of both cameras, refined on the inliers. Residual: the angle between b
and the epipolar plane of a (at camera b, as pixels_per_radian at b's pixels expect). The threshold is max_angle (radians), or max_pixels with
pixels_per_radian (N values at b's pixels, mdbrief.pixels_per_radian). Deterministic for a seed.
Returns a TwoViewResult with rotation and translation (X_a = R X_b + t, |t| = 1).)doc") +
       kOptionsDoc)
          .c_str());

  m.def(
      "fit_homography",
      [](const py::handle& a, const py::handle& b, const py::handle& scale, const py::kwargs& kwargs) {
        Inputs in = inputsFrom(a, b, scale, kwargs, "fit_homography");
        PyTwoViewResult out;
        out.kind = "homography";
        try {
          TwoViewOptions options = in.options;
          options.interruptCheck = pythonSignalCheck();
          py::gil_scoped_release release;
          HomographyResult fit = fitHomography(in.a, in.b, options, in.scale);
          out.model = fit.homography;
          out.result = std::move(fit);
        } catch (const PythonSignalRaised&) {
          throw py::error_already_set();
        } catch (const std::invalid_argument& e) {
          raiseInPythonNames(e, "fitHomography", "fit_homography");
        }
        return out;
      },
      py::arg("bearings_a"), py::arg("bearings_b"), py::kw_only(), py::arg("pixels_per_radian") = py::none(),
      (std::string(R"doc(
The homography of a plane (or a pure rotation) between matched bearings, b ~ H a with a positive
factor: RANSAC over 4 points, refined on the inliers. Residual: the angle between b and H a.
Threshold and pixels_per_radian as for fit_essential.)doc") +
       kOptionsDoc)
          .c_str());

  m.def(
      "check_known_pose",
      [](const py::handle& a, const py::handle& b, const py::handle& rotation, const py::handle& translation,
         const py::handle& scale, const py::kwargs& kwargs) {
        const Inputs in = inputsFrom(a, b, scale, kwargs, "check_known_pose");
        const RelativePose pose{matrixFrom(rotation, "rotation"), vectorFrom(translation, "translation")};
        PyTwoViewResult out;
        out.kind = "known pose";
        out.pose = pose;
        // Any scale of the translation is the same pose; one the library cannot normalise is scaled.
        RelativePose checked = pose;
        if (!directionKept(checked.translation))
          throw py::value_error("check_known_pose: translation must be finite and non-zero (with no baseline, "
                                "matches have no epipolar geometry)");
        try {
          py::gil_scoped_release release;
          out.result = checkKnownPose(in.a, in.b, checked, in.options, in.scale);
        } catch (const std::invalid_argument& e) {
          raiseInPythonNames(e, "checkKnownPose", "check_known_pose");
        }
        return out;
      },
      py::arg("bearings_a"), py::arg("bearings_b"), py::arg("rotation"), py::arg("translation"), py::kw_only(),
      py::arg("pixels_per_radian") = py::none(),
      (std::string(R"doc(
Labels matched bearings with a known relative pose (a calibrated stereo pair, odometry): camera
b's pose in camera a's frame, X_a = rotation @ X_b + translation (any scale). Inlier: the
epipolar angle within the threshold and (in_front) the point in front of both cameras. Always
ok; rotation must be a rotation and translation non-zero (ValueError).)doc") +
       kOptionsDoc)
          .c_str());

  m.def(
      "pixels_per_radian",
      [](const Camera& camera, const py::handle& pixels) {
        bool single = false;
        const auto p = pointsFromArray(pixels, 2, "pixels", single);
        const py::ssize_t n = single ? 1 : p.shape(0);
        py::array_t<double> out(n);
        for (py::ssize_t k = 0; k < n; ++k) {
          const auto s = pixelsPerRadian(camera, cv::Point2d(p.data()[2 * k], p.data()[2 * k + 1]));
          out.mutable_data()[k] = s ? *s : std::nan("");
        }
        return out;
      },
      py::arg("camera"), py::arg("pixels"), R"doc(
Pixels per radian of ray angle at each pixel (Nx2): the scale that turns an angle between rays
into pixels there, for the fits' pixels_per_radian. NaN where the camera has no ray.)doc");
}

}  // namespace mdbrief::python
