// Kalibr's camchain.yaml (kalibr_calibrate_cameras): one map per camera, cam0, cam1, ..., with
// camera_model (pinhole [fu fv pu pv], omni [xi fu fv pu pv], ds [xi alpha fu fv pu pv], eucm
// [alpha beta fu fv pu pv]), distortion_model (radtan [k1 k2 r1 r2], equidistant [k1 k2 k3 k4],
// none []), distortion_coeffs and resolution [width height]; for rigs the extrinsics T_cn_cnm1
// (maps camN-1's points into camN's) and T_cam_imu (maps the IMU's points into the camera's).
// Kalibr's pixels are OpenCV's (origin at the centre of the top-left pixel).
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

// A 4 x 4 matrix as Kalibr writes it: a list of four rows.
std::optional<RigidTransform> transformOf(const YamlReader& c, const std::string& key) {
  if (!c.has(key)) return std::nullopt;
  const YAML::Node rows = c.node(key);
  if (!rows.IsSequence() || rows.size() != 4) c.fail(key, "must be a list of 4 rows of 4 numbers");
  YAML::Node flat(YAML::NodeType::Sequence);
  for (const YAML::Node& row : rows) {
    if (!row.IsSequence() || row.size() != 4) c.fail(key, "must be a list of 4 rows of 4 numbers");
    for (const YAML::Node& value : row) flat.push_back(value);
  }
  YAML::Node holder(YAML::NodeType::Map);
  holder[key] = flat;
  const YamlReader h(c.source(), holder, c.prefix());
  return rigidTransformOf(h, key, h.numbers(key, 16, "4 x 4, row by row"));
}

}  // namespace

std::vector<std::string> kalibrCameraIds(const YAML::Node& root) { return cameraKeys(root); }

std::optional<RigidTransform> kalibrCameraToRig(const std::string& path, const YAML::Node& root, const std::string& id) {
  const YamlReader file(path, root);
  const std::vector<std::string> ids = cameraKeys(root);
  const auto at = std::find(ids.begin(), ids.end(), id);
  if (at == ids.end()) return std::nullopt;
  if (at == ids.begin()) return RigidTransform{};  // the first camera's frame is the rig's
  // cam0 -> camN through the chain: T_cN_c0 = T_cN_cN-1 ... T_c1_c0, so cam0 from camN is its inverse.
  RigidTransform camFromCam0;
  bool chained = true;
  for (auto it = ids.begin(); chained && it <= at; ++it) {
    // The chain links consecutive numbers from cam0 only: cam3 after cam1 would skip one.
    chained = *it == "cam" + std::to_string(it - ids.begin());
    if (it == ids.begin()) continue;
    const std::optional<RigidTransform> link = chained ? transformOf(file.sub(*it), "T_cn_cnm1") : std::nullopt;
    chained = link.has_value();
    if (chained) camFromCam0 = *link * camFromCam0;
  }
  if (chained) return camFromCam0.inverse();
  const std::optional<RigidTransform> camFromImu = transformOf(file.sub(*at), "T_cam_imu");
  const std::optional<RigidTransform> cam0FromImu = transformOf(file.sub(ids.front()), "T_cam_imu");
  if (camFromImu && cam0FromImu) return *cam0FromImu * camFromImu->inverse();
  return std::nullopt;
}

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
  return kalibrModelCamera(c, model, distortion, c.imageSize("resolution"), "distortion_coeffs", "Kalibr");
}

std::shared_ptr<Camera> kalibrModelCamera(const YamlReader& c, const std::string& model, const std::string& distortion,
                                          cv::Size size, const std::string& coefficientsKey, const std::string& tool) {
  const std::string& path = c.source();
  const auto intrinsics = [&](std::size_t count, const char* layout) { return c.numbers("intrinsics", count, layout); };
  const auto coefficients = [&](std::size_t count, const char* layout) {
    // Kalibr writes an empty list for none; a file without the key means the same.
    return count == 0 && !c.has(coefficientsKey) ? std::vector<double>{}
                                                 : c.numbers(coefficientsKey, count, layout);
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
  c.fail("camera_model", "'" + model + "' with distortion_model '" + distortion + "' has no camera model here (" +
                             tool + "'s supported: " + kCombinations + ")");
}

}  // namespace mdbrief::detail
