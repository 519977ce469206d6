// mdbrief.Camera and mdbrief.load_camera: the camera models behind camera.hpp, vectorised over
// numpy arrays of points.
#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera_io.hpp"

namespace mdbrief::python {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Shapes the result like the input: (N, k) for (N, k') input, (k,) for a single point.
py::array_t<double> shaped(py::ssize_t n, int k, bool single) {
  if (single) return py::array_t<double>(std::vector<py::ssize_t>{k});
  return py::array_t<double>(std::vector<py::ssize_t>{n, k});
}

py::array_t<double> pixelToBearing(const Camera& camera, const py::handle& pixels) {
  bool single = false;
  const auto in = pointsFromArray(pixels, 2, "pixels", single);
  const py::ssize_t n = single ? 1 : in.shape(0);
  auto out = shaped(n, 3, single);
  const double* p = in.data();
  double* b = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      cv::Vec3d bearing;
      const bool ok = camera.pixelToBearing({p[2 * i], p[2 * i + 1]}, bearing);
      for (int c = 0; c < 3; ++c) b[3 * i + c] = ok ? bearing[c] : kNaN;
    }
  }
  return out;
}

py::array_t<double> bearingToPixel(const Camera& camera, const py::handle& bearings) {
  bool single = false;
  const auto in = pointsFromArray(bearings, 3, "bearings", single);
  const py::ssize_t n = single ? 1 : in.shape(0);
  auto out = shaped(n, 2, single);
  const double* b = in.data();
  double* p = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      cv::Point2d pixel;
      const cv::Vec3d ray(b[3 * i], b[3 * i + 1], b[3 * i + 2]);
      const bool ok = cv::norm(ray) > 0 && camera.bearingToPixel(ray, pixel);
      p[2 * i] = ok ? pixel.x : kNaN;
      p[2 * i + 1] = ok ? pixel.y : kNaN;
    }
  }
  return out;
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
           "(N, 3) rays (any non-zero length) -> (N, 2) pixels; a row of NaN where the model\n"
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
          "save", [](const Camera& c, const std::string& path) { saveCamera(c, path); }, py::arg("path"),
          "Writes to_yaml() to path atomically.")
      .def("__repr__", [](const Camera& c) {
        return "<mdbrief.Camera " + c.modelName() + " " + std::to_string(c.imageSize().width) + "x" +
               std::to_string(c.imageSize().height) + ">";
      });

  m.def(
      "load_camera",
      [](const std::string& path) -> std::shared_ptr<Camera> {
        requireFile(path);
        try {
          return loadCamera(path);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("path"), R"doc(
Reads a calibration, recognising the format from the content: the project's YAML, OCamCalib's
calib_results.txt, or a fisheye-calib-adapter YAML. Raises FileNotFoundError for a missing file
and ValueError naming the key for a bad one.)doc");
}

}  // namespace mdbrief::python
