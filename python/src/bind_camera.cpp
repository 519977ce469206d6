// mdbrief.Camera and mdbrief.load_camera: the camera models behind camera.hpp, vectorised over
// numpy arrays of points; built from parameters named as the project's YAML keys or from
// OpenCV's K / D, and pickled as those parameters.
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <variant>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/rig.hpp"

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

py::array_t<double> bearingToPixel(const Camera& camera, const py::handle& bearings) {
  return mapPoints<3, 2>(bearings, "bearings", [&](const double* b, double* out) {
    // The library takes rays of any length (Camera::bearingToPixel); one with an infinite
    // component, which some models project to the principal point, is NaN here as documented.
    if (!std::isfinite(b[0]) || !std::isfinite(b[1]) || !std::isfinite(b[2])) return false;
    cv::Point2d pixel;
    if (!camera.bearingToPixel({b[0], b[1], b[2]}, pixel)) return false;
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

// A camera parameter from Python: a number, or a sequence of numbers (OCam's polynomials).
CameraParameter parameterFrom(const std::string& name, const py::handle& value) {
  const auto number = [&](const py::handle& v) {
    if (py::isinstance<py::bool_>(v) || !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)))
      throw py::type_error("Camera: keyword '" + name + "' must be a number" +
                           (name == "poly" || name == "inv_poly" ? std::string(" list") : std::string()));
    return v.cast<double>();
  };
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || !py::isinstance<py::iterable>(value))
    return number(value);
  std::vector<double> list;
  for (const py::handle item : value) list.push_back(number(item));
  return list;
}

py::object parameterObject(const CameraParameter& p) {
  if (const double* number = std::get_if<double>(&p)) return py::float_(*number);
  py::list list;
  for (double v : std::get<std::vector<double>>(p)) list.append(v);
  return std::move(list);
}

cv::Size sizeFrom(int width, int height) { return {width, height}; }

// An image side from Python: a value beyond a C int (2**40) is refused as out of range, in the
// words of the library's check, instead of as an argument of the wrong type.
int sideFrom(const py::int_& value, const char* keyword) {
  const int side = saturatedInt(value);
  if (side == INT_MAX || side == INT_MIN)
    throw py::value_error(std::string("Camera: keyword '") + keyword + "' must be a positive integer (got " +
                          py::repr(value).cast<std::string>() + ")");
  return side;
}

std::shared_ptr<Camera> cameraFromKeywords(const std::string& model, int width, int height, const py::dict& keywords) {
  CameraParameters parameters;
  for (const auto& [key, value] : keywords) {
    const std::string name = py::str(key);
    parameters[name] = parameterFrom(name, value);
  }
  try {
    return makeCamera(model, sizeFrom(width, height), parameters, "Camera", "keyword");
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
}

py::dict parameterDict(const Camera& camera) {
  py::dict d;
  for (const auto& [name, value] : cameraParameters(camera)) d[py::str(name)] = parameterObject(value);
  return d;
}

// K (3 x 3) and D (any shape, flattened) as cv2.fisheye.calibrate and cv2.calibrateCamera return them.
std::shared_ptr<Camera> cameraFromOpenCvArrays(const py::handle& kObject, const py::handle& dObject,
                                               std::pair<int, int> size, bool fisheye) {
  const auto k = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(kObject);
  if (!k || k.size() != 9 || (k.ndim() != 2 && k.ndim() != 1))
    throw py::value_error("Camera.from_opencv: K must be a 3 x 3 array");
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(dObject);
  if (!d) throw py::value_error("Camera.from_opencv: D must be an array of numbers");
  cv::Matx33d K;
  std::copy_n(k.data(), 9, K.val);
  const std::vector<double> D(d.data(), d.data() + d.size());
  try {
    return cameraFromOpenCv(K, D, sizeFrom(size.first, size.second), fisheye, "Camera.from_opencv");
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
}

// The options load_camera and load_rig share, ValueError naming the keyword.
CameraFileOptions fileOptions(const std::string& format, const py::handle& imageSize, const py::handle& opencvModel) {
  CameraFileOptions options;
  try {
    options.format = parseCameraFormat(format);
  } catch (const std::exception& e) {
    throw py::value_error(std::string("format: ") + e.what());
  }
  if (!imageSize.is_none()) {
    std::pair<int, int> size;
    try {
      size = imageSize.cast<std::pair<int, int>>();
    } catch (const py::cast_error&) {
      throw py::value_error("image_size must be (width, height), two integers");
    }
    if (size.first <= 0 || size.second <= 0 || size.first > 1000000 || size.second > 1000000)
      throw py::value_error("image_size must be (width, height), both in [1, 1000000], got (" +
                            std::to_string(size.first) + ", " + std::to_string(size.second) + ")");
    options.imageSize = cv::Size(size.first, size.second);
  }
  if (!opencvModel.is_none()) {
    try {
      options.opencvModel = parseOpenCvModel(py::str(opencvModel));
    } catch (const std::exception& e) {
      throw py::value_error(std::string("opencv_model: ") + e.what());
    }
  }
  return options;
}

// A camera of the rig by index or id, IndexError / KeyError as Python's containers raise.
std::size_t rigIndex(const CameraRig& rig, const py::handle& which, const char* argument) {
  if (py::isinstance<py::str>(which)) {
    try {
      return rig.index(which.cast<std::string>());
    } catch (const std::invalid_argument& e) {
      throw py::key_error(e.what());
    }
  }
  if (!py::isinstance<py::int_>(which))
    throw py::type_error(std::string(argument) + ": a camera is chosen by its index (int) or id (str), got " +
                         Py_TYPE(which.ptr())->tp_name);
  const long long i = which.cast<long long>();
  if (i < 0 || static_cast<unsigned long long>(i) >= rig.size())
    throw py::index_error("camera index " + std::to_string(i) + " out of range (the rig has " +
                          std::to_string(rig.size()) + ")");
  return static_cast<std::size_t>(i);
}

}  // namespace

void bindCamera(py::module_& m) {
  boundClass<Camera, std::shared_ptr<Camera>>(m, "Camera", R"doc(
A calibrated camera model (pinhole, radial, OCamCalib, Kannala-Brandt, double sphere, UCM/EUCM,
radial-tangential). Pixels follow OpenCV: u = column, v = row, origin at the centre of the
top-left pixel. Bearings are unit vectors, x right, y down, z along the optical axis.
Create one with mdbrief.load_camera(path), from parameters named as the YAML's keys
(configs/cameras/README.md):

    mdbrief.Camera("kannala_brandt", 1280, 800, fx=..., fy=..., cx=..., cy=..., k1=..., k2=..., k3=..., k4=...)

or from cv2.fisheye.calibrate's K and D with Camera.from_opencv(K, D, (width, height)).
Cameras pickle (as model, size and parameters).)doc")
      .def(py::init([](const std::string& model, const py::int_& width, const py::int_& height,
                       const py::kwargs& parameters) {
             return cameraFromKeywords(model, sideFrom(width, "width"), sideFrom(height, "height"), parameters);
           }),
           py::arg("model"), py::arg("width"), py::arg("height"),
           "Camera(model, width, height, **parameters): parameters are the model's keys of the project's\n"
           "YAML (mdbrief.camera_models() lists them). ValueError naming the keyword for a missing,\n"
           "unknown or bad one.")
      .def_static("from_opencv", &cameraFromOpenCvArrays, py::arg("K"), py::arg("D"), py::arg("image_size"),
                  py::arg("fisheye") = true,
                  "A camera from OpenCV's calibration: K (3 x 3), D and image_size (width, height).\n"
                  "fisheye=True: cv2.fisheye.calibrate's 4 coefficients (kannala_brandt); False:\n"
                  "cv2.calibrateCamera's 4, 5, 8, 12 or 14 (radtan).")
      .def_property_readonly("parameters", &parameterDict,
                             "The model's parameters by their YAML keys: Camera(model, width, height, **parameters)\n"
                             "is the same camera.")
      .def(py::pickle(
          [](const Camera& c) {
            return py::make_tuple(c.modelName(), c.imageSize().width, c.imageSize().height, parameterDict(c));
          },
          [](const py::tuple& t) {
            if (t.size() != 4 || !py::isinstance<py::str>(t[0]) || !py::isinstance<py::int_>(t[1]) ||
                !py::isinstance<py::int_>(t[2]) || !py::isinstance<py::dict>(t[3]))
              throw py::value_error("Camera: bad pickled state (Camera.__getstate__ gives (model: str, width: int, "
                                    "height: int, parameters: dict))");
            return cameraFromKeywords(t[0].cast<std::string>(), sideFrom(t[1], "width"), sideFrom(t[2], "height"),
                                      t[3].cast<py::dict>());
          }))
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
          "resized",
          [](const Camera& c, std::pair<int, int> size) {
            if (size.first <= 0 || size.second <= 0)
              throw py::value_error("Camera.resized: size must be (width, height), both positive, got (" +
                                    std::to_string(size.first) + ", " + std::to_string(size.second) + ")");
            return c.resized({size.first, size.second});
          },
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
      [](const py::handle& pathArgument, const std::string& format, const py::handle& cameraId,
         const py::handle& imageSize, const py::handle& opencvModel) -> std::shared_ptr<Camera> {
        const std::string path = pathFrom(pathArgument, "path");
        CameraFileOptions options = fileOptions(format, imageSize, opencvModel);
        if (!cameraId.is_none()) options.cameraId = py::str(cameraId);
        requireFile(path);
        try {
          return readCameraFile(path, options).camera;
        } catch (const std::runtime_error& e) {
          const std::string what = e.what();
          // The library's message says "by its id"; Python's spelling of the choice:
          throw py::value_error(what.find("by its id") == std::string::npos ? what : what + " (camera_id=...)");
        }
      },
      py::arg("path"), py::kw_only(), py::arg("format") = toString(CameraFormat::Auto), py::arg("camera_id") = py::none(),
      py::arg("image_size") = py::none(), py::arg("opencv_model") = py::none(),
      R"doc(
Reads a calibration (path: str, bytes or os.PathLike), recognising the format from the content
or by format= (auto, mdbrief, calib-adapter, kalibr, basalt, orbslam3, euroc, opencv, opencv-kd,
colmap, ocamcalib; configs/cameras/README.md). camera_id chooses the camera of a file that holds
several: Kalibr's 'cam0', 'cam1', ...; basalt's index; ORB-SLAM3's 1 or 2; COLMAP's CAMERA_ID.
image_size=(width, height) gives the size of a file without one (a FileStorage with K and D).
opencv_model="fisheye" or "standard" says which model four OpenCV coefficients are when the
file does not. Raises FileNotFoundError for a missing file and ValueError naming the key for a
bad one.)doc");

  boundClass<CameraRig>(m, "CameraRig", R"doc(
The cameras of a rig (mdbrief.load_rig) and the extrinsics between them. relative_pose(i, j)
returns (R, t), numpy (3, 3) and (3,), that map a point of camera j's frame into camera i's:
x_i = R @ x_j + t (t is camera j's centre seen from camera i, in the file's unit).)doc")
      .def_property_readonly("ids", [](const CameraRig& r) {
        std::vector<std::string> ids;
        for (const RigCamera& c : r.cameras()) ids.push_back(c.id);
        return ids;
      }, "The cameras' ids in the file ('cam0', '0', ...; '' for a one-camera format), or their files' paths.")
      .def_property_readonly("cameras", [](const CameraRig& r) {
        std::vector<std::shared_ptr<Camera>> cameras;
        for (const RigCamera& c : r.cameras()) cameras.push_back(c.camera);
        return cameras;
      }, "The cameras, in the order of ids.")
      .def_property_readonly("format", [](const CameraRig& r) { return toString(r.format()); },
                             "The format the file was read as.")
      .def("__len__", &CameraRig::size)
      .def(
          "camera",
          [](const CameraRig& r, const py::handle& which) { return r.at(rigIndex(r, which, "which")).camera; },
          py::arg("which"), "The camera by index (int) or id (str).")
      .def("has_relative_pose", [](const CameraRig& r, const py::handle& i, const py::handle& j) {
        return r.hasRelativePose(rigIndex(r, i, "i"), rigIndex(r, j, "j"));
      }, py::arg("i"), py::arg("j"), "Whether relative_pose(i, j) is known.")
      .def("relative_pose", [](const CameraRig& r, const py::handle& i, const py::handle& j) {
        RigidTransform pose;
        const std::size_t a = rigIndex(r, i, "i"), b = rigIndex(r, j, "j");
        try {
          pose = r.relativePose(a, b);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
        py::array_t<double> rotation({3, 3}), translation(3);
        auto R = rotation.mutable_unchecked<2>();
        auto t = translation.mutable_unchecked<1>();
        for (int row = 0; row < 3; ++row) {
          for (int col = 0; col < 3; ++col) R(row, col) = pose.rotation(row, col);
          t(row) = pose.translation[row];
        }
        return py::make_tuple(rotation, translation);
      }, py::arg("i"), py::arg("j"), R"doc(
(R, t) with x_i = R @ x_j + t: camera j's frame into camera i's (by index or id). ValueError
naming the camera when the file gives no extrinsics for it.)doc")
      .def("__repr__", [](const CameraRig& r) {
        return "<mdbrief.CameraRig " + toString(r.format()) + " of " + std::to_string(r.size()) + " cameras>";
      });

  m.def(
      "load_rig",
      [](const py::handle& paths, const std::string& format, const py::handle& imageSize,
         const py::handle& opencvModel) {
        const CameraFileOptions options = fileOptions(format, imageSize, opencvModel);
        const bool one = isPath(paths);
        std::vector<std::string> files;
        if (one) {
          files.push_back(pathFrom(paths, "paths"));
        } else {
          if (!py::isinstance<py::iterable>(paths))
            throw py::type_error(std::string("paths must be a path (str, bytes or os.PathLike) or a list of them, ") +
                                 "got " + Py_TYPE(paths.ptr())->tp_name);
          for (const py::handle& item : paths) files.push_back(pathFrom(item, "paths"));
        }
        for (const std::string& file : files) requireFile(file);
        try {
          return one ? readCameraRig(files.front(), options) : readCameraRig(files, options);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("paths"), py::kw_only(), py::arg("format") = toString(CameraFormat::Auto),
      py::arg("image_size") = py::none(), py::arg("opencv_model") = py::none(),
      R"doc(
Every camera of a calibration file (a Kalibr camchain, a basalt calib.json, ORB-SLAM3 stereo
settings, a COLMAP cameras.txt, or any one-camera file), or of a list of one-camera files
(EuRoC's cam0/sensor.yaml and cam1/sensor.yaml, placed by their T_BS), with the extrinsics the
files give: a CameraRig. format, image_size and opencv_model as for load_camera.)doc");

  m.def(
      "camera_models",
      [] {
        py::dict d;
        for (const std::string& model : cameraModelNames()) d[py::str(model)] = cameraModelKeys(model);
        return d;
      },
      "Every model name and its parameter keywords for Camera(model, width, height, **parameters).");
}

}  // namespace mdbrief::python
