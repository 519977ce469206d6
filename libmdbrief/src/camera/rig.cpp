#include "mdbrief/camera/rig.hpp"

#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"

namespace mdbrief {
namespace {

// Where each format keeps the extrinsics, for the message when a camera has none.
std::string extrinsicsKeys(CameraFormat format) {
  switch (format) {
    case CameraFormat::Kalibr: return "a Kalibr camchain keeps them in T_cn_cnm1 or T_cam_imu";
    case CameraFormat::Basalt: return "a basalt calibration keeps them in value0.T_imu_cam";
    case CameraFormat::OrbSlam3: return "ORB-SLAM3 settings keep them in Tlr or Stereo.T_c1_c2";
    case CameraFormat::Euroc: return "a EuRoC sensor.yaml keeps them in T_BS";
    default: {
      const std::string name = toString(format);
      const bool vowel = std::string("aeiou").find(name[0]) != std::string::npos;  // "an opencv-kd file"
      return (vowel ? "an " : "a ") + name + " file has none";
    }
  }
}

std::string quoted(const std::string& id) { return "'" + id + "'"; }

}  // namespace

CameraRig::CameraRig(std::string source, CameraFormat format, std::vector<RigCamera> cameras)
    : source_(std::move(source)), format_(format), cameras_(std::move(cameras)) {}

const RigCamera& CameraRig::at(std::size_t i) const {
  if (i >= cameras_.size())
    throw std::out_of_range(source_ + ": no camera " + std::to_string(i) + " (the rig has " +
                            std::to_string(cameras_.size()) + ")");
  return cameras_[i];
}

std::size_t CameraRig::index(const std::string& id) const {
  std::string list;
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    if (cameras_[i].id == id) return i;
    list += (list.empty() ? "" : ", ") + quoted(cameras_[i].id);
  }
  throw std::invalid_argument(source_ + ": no camera " + quoted(id) + " (it has " + list + ")");
}

bool CameraRig::hasRelativePose(std::size_t i, std::size_t j) const {
  return i == j || (at(i).cameraToRig && at(j).cameraToRig);
}

RigidTransform CameraRig::relativePose(std::size_t i, std::size_t j) const {
  const RigCamera& a = at(i);
  const RigCamera& b = at(j);
  if (i == j) return {};
  for (const RigCamera* c : {&a, &b})
    if (!c->cameraToRig)
      throw std::runtime_error(source_ + ": camera " + quoted(c->id) + " has no extrinsics (" +
                               extrinsicsKeys(format_) + "), so its pose relative to camera " +
                               quoted((c == &a ? b : a).id) + " is unknown");
  // x_rig = A x_i = B x_j, so x_i = A^-1 B x_j.
  const RigidTransform pose = a.cameraToRig->inverse() * *b.cameraToRig;
  // Finite translations can still overflow in the product (1e308 and -1e308 apart).
  if (!std::isfinite(pose.translation[0]) || !std::isfinite(pose.translation[1]) || !std::isfinite(pose.translation[2]))
    throw std::runtime_error(source_ + ": the pose of camera " + quoted(b.id) + " relative to camera " + quoted(a.id) +
                             " is not finite (their translations are too far apart for a double)");
  return pose;
}

RigidTransform CameraRig::relativePose(const std::string& i, const std::string& j) const {
  return relativePose(index(i), index(j));
}

namespace {

// A rig file's camera id: the folder's name for the ASL layout (cam0/sensor.yaml -> "cam0"),
// else the file's stem (left_sensor_fisheye.yaml -> "left_sensor_fisheye").
std::string fileRigId(const std::string& path) {
  const std::filesystem::path p(path);
  if (p.filename() == "sensor.yaml" && p.has_parent_path() && !p.parent_path().filename().empty() &&
      p.parent_path().filename() != "." && p.parent_path().filename() != "..")
    return p.parent_path().filename().string();
  return p.stem().string();
}

}  // namespace

CameraRig readCameraRig(const std::vector<std::string>& paths, const CameraFileOptions& options) {
  if (paths.empty()) throw std::invalid_argument("readCameraRig: no calibration file given");
  return readCameraRig(paths, std::vector<CameraFileOptions>(paths.size(), options));
}

CameraRig readCameraRig(const std::vector<std::string>& paths, const std::vector<CameraFileOptions>& options) {
  if (paths.empty()) throw std::invalid_argument("readCameraRig: no calibration file given");
  if (options.size() != paths.size())
    throw std::invalid_argument("readCameraRig: " + std::to_string(options.size()) + " file options for " +
                                std::to_string(paths.size()) + " files");
  for (const CameraFileOptions& o : options)
    if (!o.cameraId.empty())
      throw std::invalid_argument("readCameraRig: a rig of files takes each file's only camera; the camera choice '" +
                                  o.cameraId + "' does not apply");
  std::vector<RigCamera> cameras;
  std::string source;
  CameraFormat format = CameraFormat::Auto;
  for (size_t k = 0; k < paths.size(); ++k) {
    const std::string& path = paths[k];
    const CameraRig one = readCameraRig(path, options[k]);
    // The same file under two names (./cams/e0.yaml and cams/e0.yaml, a link) would make a rig
    // whose cameras coincide.
    for (size_t j = 0; j < k; ++j) {
      std::error_code error;
      if (std::filesystem::equivalent(paths[j], path, error))
        throw std::invalid_argument(path + ": the same file as " + paths[j] + ", given twice in the rig's files");
    }
    if (one.size() != 1)
      throw std::runtime_error(path + ": holds " + std::to_string(one.size()) +
                               " cameras; a rig of files takes one camera per file (read this file alone as a rig)");
    // A camera without extrinsics cannot be placed among the others: its own frame is no rig's.
    RigCamera camera = one.at(0);
    camera.id = fileRigId(path);
    if (one.format() != CameraFormat::Euroc) camera.cameraToRig.reset();
    cameras.push_back(std::move(camera));
    if (format == CameraFormat::Auto) format = one.format();
    source += (source.empty() ? "" : ", ") + path;
  }
  // Ids that two files share (two sensor.yaml in folders of one name) give way to the paths.
  std::set<std::string> ids;
  for (const auto& c : cameras) ids.insert(c.id);
  if (ids.size() != cameras.size())
    for (size_t k = 0; k < cameras.size(); ++k) cameras[k].id = paths[k];
  return CameraRig(source, format, std::move(cameras));
}

namespace detail {

RigidTransform rigidTransformOf(const YamlReader& r, const std::string& key, const std::vector<double>& m) {
  if (m.size() == 16 && (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0))
    r.fail(key, "must end with the row 0 0 0 1");
  const cv::Matx33d rotation(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
  const double offBy = cv::norm(rotation.t() * rotation - cv::Matx33d::eye(), cv::NORM_INF);
  if (offBy > 1e-3 || cv::determinant(rotation) <= 0.0)
    r.fail(key, "has no rotation in its upper-left 3 x 3 (R^T R differs from I by " + std::to_string(offBy) +
                    ", det " + std::to_string(cv::determinant(rotation)) + ")");
  // The nearest rotation, so that chains and inverses stay rigid.
  cv::Mat w, u, vt;
  cv::SVDecomp(cv::Mat(rotation), w, u, vt);
  const cv::Mat nearest = u * vt;
  return {cv::Matx33d(nearest), {m[3], m[7], m[11]}};
}

}  // namespace detail
}  // namespace mdbrief
