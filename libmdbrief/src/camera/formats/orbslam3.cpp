// ORB-SLAM3's settings file (an OpenCV FileStorage YAML, "%YAML:1.0"): Camera.type PinHole
// (k1 k2 p1 p2, optional k3; without them an undistorted pinhole), KannalaBrandt8 (k1..k4) or
// Rectified (a pinhole), the image size Camera.width and Camera.height, and the intrinsics under
// the old flat keys (Camera.fx, ...; the second camera of a stereo rig Camera2.fx, ...) or,
// with File.version "1.0", the newer Camera1.fx and Camera2.fx. The cameras are "1" and "2".
// ORB-SLAM3's pixels are OpenCV's.
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

std::shared_ptr<Camera> readOrbSlam3Settings(const std::string& path, const YAML::Node& root,
                                             const std::string& camera) {
  const YamlReader r(path, root);
  const std::string type = r.text("Camera.type");
  if (type != "PinHole" && type != "KannalaBrandt8" && type != "Rectified")
    r.fail("Camera.type", "'" + type + "' is not one of: PinHole, KannalaBrandt8, Rectified");
  const bool newKeys = r.has("File.version");
  std::vector<std::string> ids;
  for (const char* id : {"1", "2"})
    if (r.has(prefixOf(newKeys, id) + "fx")) ids.push_back(id);
  if (ids.empty()) ids.push_back("1");  // so that the missing key is named below
  const std::string prefix = prefixOf(newKeys, chooseCamera(path, "the ORB-SLAM3 settings", ids, camera));
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
