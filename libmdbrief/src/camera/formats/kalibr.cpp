// Kalibr's camchain.yaml (kalibr_calibrate_cameras): one map per camera, cam0, cam1, ..., with
// camera_model (pinhole [fu fv pu pv], omni [xi fu fv pu pv], ds [xi alpha fu fv pu pv], eucm
// [alpha beta fu fv pu pv]), distortion_model (radtan [k1 k2 r1 r2], equidistant [k1 k2 k3 k4],
// none []), distortion_coeffs and resolution [width height]; the extrinsics and topics are not
// read. Kalibr's pixels are OpenCV's (origin at the centre of the top-left pixel).
#include <algorithm>
#include <cctype>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/double_sphere.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/omni.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/radtan.hpp"
#include "mdbrief/camera/unified.hpp"

namespace mdbrief::detail {
namespace {

bool isCameraKey(const std::string& key) {
  return key.size() > 3 && key.compare(0, 3, "cam") == 0 &&
         std::all_of(key.begin() + 3, key.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

// camN keys in camera order (cam2 before cam10).
std::vector<std::string> cameraKeys(const YAML::Node& root) {
  std::vector<std::string> keys;
  for (const auto& kv : root)
    if (kv.first.IsScalar() && isCameraKey(kv.first.Scalar())) keys.push_back(kv.first.Scalar());
  std::sort(keys.begin(), keys.end(), [](const std::string& a, const std::string& b) {
    return a.size() != b.size() ? a.size() < b.size() : a < b;
  });
  return keys;
}

const char* const kCombinations = "pinhole-radtan, pinhole-equidistant, pinhole-none, omni-radtan, omni-none, "
                                  "ds-none, eucm-none";

}  // namespace

bool isKalibrCamchain(const YAML::Node& root) {
  for (const std::string& key : cameraKeys(root))
    if (root[key].IsMap() && root[key]["camera_model"]) return true;
  return false;
}

std::shared_ptr<Camera> readKalibrCamchain(const std::string& path, const YAML::Node& root, const std::string& camera) {
  const YamlReader file(path, root);
  const std::string name = chooseCamera(path, "the Kalibr camchain", cameraKeys(root), camera);
  const YamlReader c = file.sub(name);
  const std::string model = c.text("camera_model");
  const std::string distortion = c.text("distortion_model");
  const cv::Size size = c.imageSize("resolution");
  const auto intrinsics = [&](std::size_t count, const char* layout) { return c.numbers("intrinsics", count, layout); };
  const auto coefficients = [&](std::size_t count, const char* layout) {
    // Kalibr writes an empty list for none; a file without the key means the same.
    return count == 0 && !c.has("distortion_coeffs") ? std::vector<double>{}
                                                      : c.numbers("distortion_coeffs", count, layout);
  };
  const auto linear = [&](const std::vector<double>& v, std::size_t at) {
    return CameraIntrinsics{size.width, size.height, v[at], v[at + 1], v[at + 2], v[at + 3]};
  };
  const std::string combination = model + "-" + distortion;
  if (combination == "pinhole-radtan") {
    const auto k = intrinsics(4, "fu fv pu pv");
    const auto d = coefficients(4, "k1 k2 r1 r2");
    return construct<RadTanCamera>(path, RadTanParams{linear(k, 0), d[0], d[1], d[2], d[3]});
  }
  if (combination == "pinhole-equidistant") {
    const auto k = intrinsics(4, "fu fv pu pv");
    const auto d = coefficients(4, "k1 k2 k3 k4");
    return construct<KannalaBrandtCamera>(path, KannalaBrandtParams{linear(k, 0), d[0], d[1], d[2], d[3]});
  }
  if (combination == "pinhole-none") {
    coefficients(0, "none");
    return construct<PinholeCamera>(path, linear(intrinsics(4, "fu fv pu pv"), 0));
  }
  if (combination == "omni-radtan" || combination == "omni-none") {
    const auto k = intrinsics(5, "xi fu fv pu pv");
    const auto d = distortion == "radtan" ? coefficients(4, "k1 k2 r1 r2") : std::vector<double>(4, 0.0);
    if (distortion == "none") coefficients(0, "none");
    return construct<OmniCamera>(path, OmniParams{linear(k, 1), k[0], d[0], d[1], d[2], d[3]});
  }
  if (combination == "ds-none") {
    const auto k = intrinsics(6, "xi alpha fu fv pu pv");
    coefficients(0, "none");
    return construct<DoubleSphereCamera>(path, DoubleSphereParams{linear(k, 2), k[0], k[1]});
  }
  if (combination == "eucm-none") {
    const auto k = intrinsics(6, "alpha beta fu fv pu pv");
    coefficients(0, "none");
    return construct<UnifiedCamera>(path, UnifiedParams{linear(k, 2), k[0], k[1]});
  }
  c.fail("camera_model", "'" + model + "' with distortion_model '" + distortion +
                             "' has no camera model here (Kalibr's supported: " + kCombinations + ")");
}

}  // namespace mdbrief::detail
