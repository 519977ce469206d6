// basalt's calib.json (cereal's JSON, read as YAML): value0.intrinsics is a list of
// {camera_type, intrinsics: {fx, fy, cx, cy, ...}} and value0.resolution the list of
// [width, height], one entry per camera; a camera is chosen by its index ("0", "1", ...). The
// camera types kb4, ds, eucm, ucm (basalt's alpha form, as camera/unified.hpp), pinhole-radtan8
// (its rpmax, the radius of the one-to-one area on the z = 1 plane, 0 = none) and pinhole are
// read, and for rigs value0.T_imu_cam, one {px, py, pz, qx, qy, qz, qw} per camera (maps the
// camera's points into the IMU's); the IMU entries are not. Basalt's pixels are OpenCV's.
#include <cmath>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/double_sphere.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/radtan.hpp"
#include "mdbrief/camera/unified.hpp"

namespace mdbrief::detail {

bool isBasaltCalibration(const YAML::Node& root) {
  const YAML::Node value = root["value0"];
  return value && value.IsMap() && value["intrinsics"];
}

std::vector<std::string> basaltCameraIds(const std::string& path, const YAML::Node& root) {
  const YamlReader value = YamlReader(path, root).sub("value0");
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < value.count("intrinsics"); ++i) ids.push_back(std::to_string(i));
  return ids;
}

std::optional<RigidTransform> basaltCameraToRig(const std::string& path, const YAML::Node& root, const std::string& id) {
  const YamlReader value = YamlReader(path, root).sub("value0");
  const std::size_t index = std::stoul(id);
  if (!value.has("T_imu_cam") || index >= value.count("T_imu_cam")) return std::nullopt;
  const YamlReader pose = value.elementMap("T_imu_cam", index);
  pose.requireOnly({"px", "py", "pz", "qx", "qy", "qz", "qw"}, "basalt T_imu_cam");
  const cv::Vec4d q(pose.number("qw"), pose.number("qx"), pose.number("qy"), pose.number("qz"));
  // Written normalised to the digits kept; anything further off is no rotation.
  if (std::abs(cv::norm(q) - 1.0) > 1e-3) pose.fail("qw", "with qx, qy, qz is no unit quaternion (norm " +
                                                          std::to_string(cv::norm(q)) + ")");
  const cv::Vec4d u = q / cv::norm(q);
  const double w = u[0], x = u[1], y = u[2], z = u[3];
  const cv::Matx33d r(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),  //
                      2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),  //
                      2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y));
  return RigidTransform{r, {pose.number("px"), pose.number("py"), pose.number("pz")}};
}

std::shared_ptr<Camera> readBasaltCalibration(const std::string& path, const YAML::Node& root,
                                              const std::string& camera) {
  const YamlReader value = YamlReader(path, root).sub("value0");
  const std::vector<std::string> ids = basaltCameraIds(path, root);
  const std::size_t index = std::stoul(chooseCamera(path, "the basalt calibration", ids, camera));
  const YamlReader entry = value.elementMap("intrinsics", index);
  const cv::Size size = value.elementImageSize("resolution", index);
  const std::string type = entry.text("camera_type");
  const YamlReader p = entry.sub("intrinsics");
  const auto keys = [&](std::set<std::string> extra) {
    extra.insert({"fx", "fy", "cx", "cy"});
    p.requireOnly(extra, "basalt " + type);
    return CameraIntrinsics{size.width, size.height, p.number("fx"), p.number("fy"), p.number("cx"), p.number("cy")};
  };
  if (type == "kb4") {
    const CameraIntrinsics k = keys({"k1", "k2", "k3", "k4"});
    return construct<KannalaBrandtCamera>(
        path, KannalaBrandtParams{k, p.number("k1"), p.number("k2"), p.number("k3"), p.number("k4")});
  }
  if (type == "ds") {
    const CameraIntrinsics k = keys({"xi", "alpha"});
    return construct<DoubleSphereCamera>(path, DoubleSphereParams{k, p.number("xi"), p.number("alpha")});
  }
  if (type == "eucm") {
    const CameraIntrinsics k = keys({"alpha", "beta"});
    return construct<UnifiedCamera>(path, UnifiedParams{k, p.number("alpha"), p.number("beta")});
  }
  if (type == "ucm") {
    const CameraIntrinsics k = keys({"alpha"});
    return construct<UnifiedCamera>(path, UnifiedParams{k, p.number("alpha"), 1.0});
  }
  if (type == "pinhole-radtan8") {
    const CameraIntrinsics k = keys({"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "rpmax"});
    RadTanParams r{k, p.number("k1"), p.number("k2"), p.number("p1"), p.number("p2"), p.number("k3")};
    r.k4 = p.number("k4");
    r.k5 = p.number("k5");
    r.k6 = p.number("k6");
    r.maxRadius = p.number("rpmax", 0.0);
    if (r.maxRadius < 0.0) p.fail("rpmax", "must be >= 0 (0: no limit)");
    return construct<RadTanCamera>(path, r);
  }
  if (type == "pinhole") return construct<PinholeCamera>(path, keys({}));
  entry.fail("camera_type", "'" + type + "' has no camera model here (basalt's supported: kb4, ds, eucm, ucm, "
                                         "pinhole-radtan8, pinhole)");
}

}  // namespace mdbrief::detail
