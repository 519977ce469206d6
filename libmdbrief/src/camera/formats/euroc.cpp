// The sensor.yaml of the EuRoC MAV dataset's camera folders (cam0/sensor.yaml, ...), which TUM VI
// ships too and Kimera-VIO reads as its LeftCameraParams.yaml / RightCameraParams.yaml:
// sensor_type (camera), T_BS ({cols: 4, rows: 4, data: [16 numbers, row by row]}, maps the
// camera's points into the body's), rate_hz, resolution [width height], camera_model,
// intrinsics [fu fv cu cv], distortion_model and distortion_coefficients.
//  - camera_model pinhole with distortion_model radtan, radial-tangential or plumb_bob (k1 k2 p1
//    p2 [k3]) -> radtan; equidistant (k1 k2 k3 k4) -> kannala_brandt; none -> pinhole;
//  - camera_model omni with distortion_model radtan or none and intrinsics [xi fu fv cu cv] (the
//    unified model as Kalibr writes it) -> omni; ds and eucm as in Kalibr;
//  - camera_model omni with distortion_model omni (Kimera-VIO's OCamCalib cameras): the forward
//    polynomial a0.. in distortion_coefficients, omni_distortion_center [x y] (pixels) and
//    omni_affine [A0 A1 A2], which Kimera reads as (x, y) - centre = [1 A0; A1 A2] (x', y') with
//    (x', y', f(rho)) the ray -> ocam (its inverse polynomial fitted; the intrinsics, Kimera's
//    ideal pinhole for this model, are not read). The lens is read as OCamCalib defines it: a
//    pixel right of the centre sees to the right. Kimera divides by f(rho), which OCamCalib's
//    negative a0 makes negative, so its rays are these turned 180 degrees about the axis.
// The model names are read case-insensitively, as Kimera does. The pixels are OpenCV's.
#include <algorithm>
#include <cctype>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/ocam.hpp"
#include "mdbrief/camera/radtan.hpp"

namespace mdbrief::detail {
namespace {

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

const char* const kDistortionModels = "radtan, radial-tangential, plumb_bob, equidistant, none; omni with "
                                      "camera_model omni";

}  // namespace

bool isEurocSensor(const YAML::Node& root) {
  return root["sensor_type"] || (root["camera_model"] && root["resolution"]);
}

std::shared_ptr<Camera> readEurocSensor(const std::string& path, const YAML::Node& root) {
  const YamlReader r(path, root);
  if (r.has("sensor_type") && lowerCase(r.text("sensor_type")) != "camera")
    r.fail("sensor_type", "is '" + r.text("sensor_type") + "', not camera");
  const cv::Size size = r.imageSize("resolution");
  const std::string model = lowerCase(r.text("camera_model"));
  if (model != "pinhole" && model != "omni" && model != "ds" && model != "eucm")
    r.fail("camera_model", "names an unknown model '" + r.text("camera_model") + "' (known: pinhole, omni, ds, eucm)");
  if (!r.has("distortion_model"))
    r.fail("distortion_model", "is missing (one of: " + std::string(kDistortionModels) + ")");
  const std::string distortion = lowerCase(r.text("distortion_model"));
  if (model == "omni" && distortion == "omni") {
    OcamParams p;
    p.width = size.width;
    p.height = size.height;
    p.forward = r.numbers("distortion_coefficients");
    if (p.forward.size() < 2) r.fail("distortion_coefficients", "needs at least 2 numbers (a0 a1 ...)");
    const std::vector<double> centre = r.numbers("omni_distortion_center", 2, "x y");
    const std::vector<double> affine = r.numbers("omni_affine", 3, "A0 A1 A2");
    // OcamParams is on (row, column): row - v0 = c x_o + d y_o, column - u0 = e x_o + y_o with
    // x_o = y', y_o = x'.
    p.u0 = centre[0];
    p.v0 = centre[1];
    p.c = affine[2];
    p.d = affine[1];
    p.e = affine[0];
    return makeOcam(path, p);
  }
  if (model == "pinhole" && (distortion == "radtan" || distortion == "radial-tangential" || distortion == "plumb_bob")) {
    // ROS's plumb_bob has a fifth coefficient, k3.
    if (r.has("distortion_coefficients") && r.node("distortion_coefficients").IsSequence() &&
        r.node("distortion_coefficients").size() == 5) {
      const auto k = r.numbers("intrinsics", 4, "fu fv cu cv");
      const auto d = r.numbers("distortion_coefficients", 5, "k1 k2 p1 p2 k3");
      return construct<RadTanCamera>(
          path, RadTanParams{{size.width, size.height, k[0], k[1], k[2], k[3]}, d[0], d[1], d[2], d[3], d[4]});
    }
    return kalibrModelCamera(r, model, "radtan", size, "distortion_coefficients", "EuRoC");
  }
  if (distortion == "radtan" || distortion == "radial-tangential" || distortion == "plumb_bob")
    return kalibrModelCamera(r, model, "radtan", size, "distortion_coefficients", "EuRoC");
  if (distortion == "equidistant" || distortion == "none")
    return kalibrModelCamera(r, model, distortion, size, "distortion_coefficients", "EuRoC");
  r.fail("distortion_model", "names an unknown model '" + r.text("distortion_model") + "' (known: " +
                                 kDistortionModels + ")");
}

std::optional<RigidTransform> eurocCameraToRig(const std::string& path, const YAML::Node& root) {
  const YamlReader r(path, root);
  if (!r.has("T_BS")) return std::nullopt;
  const YamlReader t = r.sub("T_BS");
  if (t.size("rows") != 4 || t.size("cols") != 4) r.fail("T_BS", "must be 4 x 4 (rows: 4, cols: 4)");
  return rigidTransformOf(r, "T_BS", t.numbers("data", 16, "4 x 4, row by row"));
}

}  // namespace mdbrief::detail
