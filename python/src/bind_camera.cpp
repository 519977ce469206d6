// mdbrief.Camera and mdbrief.load_camera: the camera models behind camera.hpp, vectorised over
// numpy arrays of points.
#include <algorithm>
#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera_io.hpp"

namespace mdbrief::python {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Applies `convert` (in: `In` numbers of one point, out: `Out` numbers, false = no result) to
// every point of an (N, In) or (In,) array without the GIL; rows without a result are NaN.
template <int In, int Out, typename Convert>
py::array_t<double> mapPoints(const py::handle& points, const char* argument, Convert convert) {
  bool single = false;
  const auto in = pointsFromArray(points, In, argument, single);
  const py::ssize_t n = single ? 1 : in.shape(0);
  py::array_t<double> out = single ? py::array_t<double>(std::vector<py::ssize_t>{Out})
                                   : py::array_t<double>(std::vector<py::ssize_t>{n, Out});
  const double* src = in.data();
  double* dst = out.mutable_data();
  py::gil_scoped_release release;
  for (py::ssize_t i = 0; i < n; ++i)
    if (!convert(src + In * i, dst + Out * i)) std::fill_n(dst + Out * i, Out, kNaN);
  return out;
}

py::array_t<double> pixelToBearing(const Camera& camera, const py::handle& pixels) {
  return mapPoints<2, 3>(pixels, "pixels", [&](const double* p, double* out) {
    cv::Vec3d bearing;
    if (!camera.pixelToBearing({p[0], p[1]}, bearing)) return false;
    std::copy_n(bearing.val, 3, out);
    return true;
  });
}

// The models square a ray's components, which overflows or underflows at the extremes of double
// (Camera::bearingToPixel): such a ray is scaled to a largest component of 1, which keeps its
// direction. Others are passed unchanged, so the pixels are the C++ library's bit for bit.
bool scaledRay(const double* b, cv::Vec3d& ray) {
  const double largest = std::max({std::abs(b[0]), std::abs(b[1]), std::abs(b[2])});
  // NaN compares false, so the largest component alone does not show one.
  if (!(largest > 0) || !std::isfinite(largest) || std::isnan(b[0]) || std::isnan(b[1]) || std::isnan(b[2]))
    return false;
  ray = cv::Vec3d(b[0], b[1], b[2]);
  // Divided one by one: cv::Vec's /= multiplies by 1 / largest, infinite for a subnormal ray.
  if (largest > 1e150 || largest < 1e-150) ray = cv::Vec3d(b[0] / largest, b[1] / largest, b[2] / largest);
  return true;
}

py::array_t<double> bearingToPixel(const Camera& camera, const py::handle& bearings) {
  return mapPoints<3, 2>(bearings, "bearings", [&](const double* b, double* out) {
    cv::Vec3d ray;
    cv::Point2d pixel;
    if (!scaledRay(b, ray) || !camera.bearingToPixel(ray, pixel)) return false;
    out[0] = pixel.x, out[1] = pixel.y;
    return true;
  });
}

py::object isValid(const Camera& camera, const py::handle& pixels) {
  bool single = false;
  const auto in = pointsFromArray(pixels, 2, "pixels", single);
  if (single) return py::bool_(camera.isValid({in.data()[0], in.data()[1]}));
  py::array_t<bool> out(in.shape(0));
  for (py::ssize_t i = 0; i < in.shape(0); ++i) out.mutable_data()[i] = camera.isValid({in.at(i, 0), in.at(i, 1)});
  return std::move(out);
}

}  // namespace

void bindCamera(py::module_& m) {
  py::class_<Camera, std::shared_ptr<Camera>>(m, "Camera", R"doc(
A calibrated camera model (pinhole, radial, OCamCalib, Kannala-Brandt, double sphere, UCM/EUCM,
radial-tangential). Pixels follow OpenCV: u = column, v = row, origin at the centre of the
top-left pixel. Bearings are unit vectors, x right, y down, z along the optical axis.
Create one with mdbrief.load_camera(path).)doc")
      .def_property_readonly("model", &Camera::modelName, "Model name as in the project's YAML ('ocam', ...).")
      .def_property_readonly(
          "image_size", [](const Camera& c) { return py::make_tuple(c.imageSize().width, c.imageSize().height); },
          "(width, height) of the calibration.")
      .def_property_readonly("width", [](const Camera& c) { return c.imageSize().width; })
      .def_property_readonly("height", [](const Camera& c) { return c.imageSize().height; })
      .def_property_readonly("tangent_plane_scale", &Camera::tangentPlaneScale,
                             "Scale of the tangent plane dBRIEF describes on (pixels per unit).")
      .def("pixel_to_bearing", &pixelToBearing, py::arg("pixels"),
           "(N, 2) pixels -> (N, 3) unit bearings; a row of NaN where the model has no inverse.\n"
           "A single (2,) pixel gives a (3,) bearing.")
      .def("bearing_to_pixel", &bearingToPixel, py::arg("bearings"),
           "(N, 3) rays (any finite non-zero length) -> (N, 2) pixels; a row of NaN where the model\n"
           "cannot project the ray. The pixel may lie outside the image: see is_valid.")
      .def("is_valid", &isValid, py::arg("pixels"),
           "(N, 2) pixels -> (N,) bool: inside the image and the lens' usable area.")
      .def(
          "resized", [](const Camera& c, std::pair<int, int> size) { return c.resized({size.first, size.second}); },
          py::arg("size"), "The same lens at another (width, height) (a uniform resample of the image).")
      .def(
          "to_yaml", [](const Camera& c) { return cameraToYaml(c); },
          "The calibration in the project's YAML schema (configs/cameras/README.md).")
      .def(
          "save", [](const Camera& c, const py::handle& path) { saveCamera(c, pathFrom(path, "path")); },
          py::arg("path"), "Writes to_yaml() to path (str, bytes or os.PathLike) atomically.")
      .def("__repr__", [](const Camera& c) {
        return "<mdbrief.Camera " + c.modelName() + " " + std::to_string(c.imageSize().width) + "x" +
               std::to_string(c.imageSize().height) + ">";
      });

  m.def(
      "load_camera",
      [](const py::handle& pathArgument) -> std::shared_ptr<Camera> {
        const std::string path = pathFrom(pathArgument, "path");
        requireFile(path);
        try {
          return loadCamera(path);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("path"), R"doc(
Reads a calibration (path: str, bytes or os.PathLike), recognising the format from the content:
the project's YAML, OCamCalib's calib_results.txt, or a fisheye-calib-adapter YAML. Raises
FileNotFoundError for a missing file and ValueError naming the key for a bad one.)doc");
}

}  // namespace mdbrief::python
