// ORB-SLAM3's settings file (an OpenCV FileStorage YAML, "%YAML:1.0"): Camera.type PinHole
// (k1 k2 p1 p2, optional k3; without them an undistorted pinhole), KannalaBrandt8 (k1..k4) or
// Rectified (a pinhole), the image size Camera.width and Camera.height, and the intrinsics under
// the old flat keys (Camera.fx, ...; the second camera of a stereo rig Camera2.fx, ...) or,
// with File.version "1.0", the newer Camera1.fx and Camera2.fx. The cameras are "1" and "2".
// For rigs, camera 2's extrinsics: Tlr (old keys, 3 x 4) or Stereo.T_c1_c2 (4 x 4), which map
// its points into camera 1's. ORB-SLAM3's pixels are OpenCV's.
#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/radtan.hpp"

namespace mdbrief::detail {
namespace {

// The key prefix of camera "1" or "2".
std::string prefixOf(bool newKeys, const std::string& id) {
  if (newKeys) return "Camera" + id + ".";
  return id == "1" ? "Camera." : "Camera2.";
}

}  // namespace

bool isOrbSlam3Settings(const YAML::Node& root) { return static_cast<bool>(root["Camera.type"]); }

std::vector<std::string> orbSlam3CameraIds(const YAML::Node& root) {
  const bool newKeys = static_cast<bool>(root["File.version"]);
  std::vector<std::string> ids;
  for (const char* id : {"1", "2"})
    if (root[prefixOf(newKeys, id) + "fx"]) ids.push_back(id);
  if (ids.empty()) ids.push_back("1");  // so that the missing key is named when it is read
  return ids;
}

std::optional<RigidTransform> orbSlam3CameraToRig(const std::string& path, const YAML::Node& root,
                                                  const std::string& id) {
  if (id == "1") return RigidTransform{};
  const YamlReader r(path, root);
  for (const char* key : {"Tlr", "Stereo.T_c1_c2"}) {
    if (!r.has(key)) continue;
    int rows = 0, cols = 0;
    const std::vector<double> m = openCvMatrix(r, key, rows, cols);
    if (cols != 4 || (rows != 3 && rows != 4)) r.fail(key, "must be 3 x 4 or 4 x 4");
    return rigidTransformOf(r, key, m);
  }
  return std::nullopt;
}

std::shared_ptr<Camera> readOrbSlam3Settings(const std::string& path, const YAML::Node& root,
                                             const std::string& camera) {
  const YamlReader r(path, root);
  const std::string type = r.text("Camera.type");
  if (type != "PinHole" && type != "KannalaBrandt8" && type != "Rectified")
    r.fail("Camera.type", "'" + type + "' is not one of: PinHole, KannalaBrandt8, Rectified");
  const bool newKeys = r.has("File.version");
  const std::string prefix =
      prefixOf(newKeys, chooseCamera(path, "the ORB-SLAM3 settings", orbSlam3CameraIds(root), camera));
  const CameraIntrinsics k{r.size("Camera.width"), r.size("Camera.height"), r.number(prefix + "fx"),
                           r.number(prefix + "fy"),  r.number(prefix + "cx"),     r.number(prefix + "cy")};
  const auto coefficient = [&](const char* name) { return r.number(prefix + name); };
  if (type == "KannalaBrandt8")
    return construct<KannalaBrandtCamera>(
        path, KannalaBrandtParams{k, coefficient("k1"), coefficient("k2"), coefficient("k3"), coefficient("k4")});
  if (type == "PinHole") {
    // The newer keys make the distortion optional; the old ones always have it.
    if (newKeys && !r.has(prefix + "k1") && !r.has(prefix + "k2") && !r.has(prefix + "p1") && !r.has(prefix + "p2"))
      return construct<PinholeCamera>(path, k);
    return construct<RadTanCamera>(path, RadTanParams{k, coefficient("k1"), coefficient("k2"), coefficient("p1"),
                                                      coefficient("p2"), r.number(prefix + "k3", 0.0)});
  }
  return construct<PinholeCamera>(path, k);  // Rectified
}

}  // namespace mdbrief::detail
