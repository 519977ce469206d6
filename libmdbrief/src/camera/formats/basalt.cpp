// basalt's calib.json (cereal's JSON, read as YAML): value0.intrinsics is a list of
// {camera_type, intrinsics: {fx, fy, cx, cy, ...}} and value0.resolution the list of
// [width, height], one entry per camera; a camera is chosen by its index ("0", "1", ...). The
// camera types kb4, ds, eucm, ucm (basalt's alpha form, as camera/unified.hpp), pinhole-radtan8
// (its rpmax, the radius of the one-to-one area on the z = 1 plane, 0 = none) and pinhole are
// read; the IMU and extrinsic entries are not. Basalt's pixels are OpenCV's.
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

std::shared_ptr<Camera> readBasaltCalibration(const std::string& path, const YAML::Node& root,
                                              const std::string& camera) {
  const YamlReader value = YamlReader(path, root).sub("value0");
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < value.count("intrinsics"); ++i) ids.push_back(std::to_string(i));
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
