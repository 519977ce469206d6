#pragma once
// Camera rigs: the cameras of a calibration file that holds several (Kalibr camchain, basalt
// calib.json, ORB-SLAM3 stereo settings, COLMAP cameras.txt) or of several files (EuRoC /
// Kimera sensor.yaml files, one per camera), with the extrinsics the files give, so that the
// relative pose between any two cameras can be asked for (configs/cameras/README.md "Rigs").
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/io.hpp"

namespace mdbrief {

// A rotation and a translation that map a point's coordinates in one frame ("from") to its
// coordinates in another ("to"): x_to = rotation * x_from + translation. The rotation is proper
// (orthonormal, determinant +1); the translation is in the calibration's unit (metres for
// Kalibr, basalt, EuRoC and ORB-SLAM3).
struct RigidTransform {
  cv::Matx33d rotation = cv::Matx33d::eye();
  cv::Vec3d translation{0.0, 0.0, 0.0};

  cv::Vec3d apply(const cv::Vec3d& point) const { return rotation * point + translation; }
  // Maps "to" back to "from".
  RigidTransform inverse() const { return {rotation.t(), -(rotation.t() * translation)}; }
  // (a * b).apply(x) == a.apply(b.apply(x)).
  friend RigidTransform operator*(const RigidTransform& a, const RigidTransform& b) {
    return {a.rotation * b.rotation, a.rotation * b.translation + a.translation};
  }
};

// One camera of a rig.
struct RigCamera {
  // Its id in the file (as CameraFileOptions::cameraId chooses it: "cam0", "0", "1", COLMAP's
  // CAMERA_ID; empty for a one-camera format). In a rig of files, the file's: its folder's name
  // in the ASL layout (cam0/sensor.yaml -> "cam0"), else its stem (left.yaml -> "left"); the
  // paths as given when two files would share one.
  std::string id;
  std::shared_ptr<Camera> camera;
  // Maps the camera's frame (camera.hpp: x right, y down, z forward) into the rig's reference
  // frame: Kalibr's cam0, basalt's IMU, EuRoC's body (T_BS), ORB-SLAM3's camera 1. None when the
  // file gives no extrinsics for it.
  std::optional<RigidTransform> cameraToRig;
};

class CameraRig {
 public:
  CameraRig(std::string source, CameraFormat format, std::vector<RigCamera> cameras);

  // The file, or the files joined by ", ", for messages.
  const std::string& source() const { return source_; }
  // The format the cameras were read as (never auto; of the first file in a rig of files).
  CameraFormat format() const { return format_; }
  std::size_t size() const { return cameras_.size(); }
  const std::vector<RigCamera>& cameras() const { return cameras_; }
  const RigCamera& at(std::size_t i) const;  // std::out_of_range naming the count
  // The index of a camera id; std::invalid_argument listing the ids for an unknown one.
  std::size_t index(const std::string& id) const;
  // Whether relativePose(i, j) has what it needs (i == j always does).
  bool hasRelativePose(std::size_t i, std::size_t j) const;

  // Maps points of camera j's frame into camera i's frame: x_i = R x_j + t. So t is camera j's
  // centre in camera i's frame, and a bearing b_j of camera j is R b_j seen from camera i: the
  // RelativePose of geometry/two_view.hpp with a = i and b = j.
  // Identity for i == j. Throws std::runtime_error naming the source, the camera and where its
  // format keeps extrinsics when either camera has none; std::out_of_range for a bad index.
  RigidTransform relativePose(std::size_t i, std::size_t j) const;
  RigidTransform relativePose(const std::string& i, const std::string& j) const;

 private:
  std::string source_;
  CameraFormat format_;
  std::vector<RigCamera> cameras_;
};

// Every camera of a calibration file, in file order, with its extrinsics. options.format
// chooses the format as for readCameraFile; options.cameraId must be empty (the rig holds them
// all), options.imageSize and options.opencvModel apply. Throws as readCameraFile.
CameraRig readCameraRig(const std::string& path, const CameraFileOptions& options = {});

// A rig of one-camera files (EuRoC's cam0/sensor.yaml and cam1/sensor.yaml), in the order
// given, each camera's id from its file (RigCamera::id: "cam0", "cam1"). Only EuRoC's T_BS places the cameras of separate files
// (all relative to the same body); a camera of another format has no extrinsics in such a rig. Throws std::runtime_error naming a file that holds
// several cameras, or std::invalid_argument for no path, a file given twice (under any name)
// or a camera choice in options.
CameraRig readCameraRig(const std::vector<std::string>& paths, const CameraFileOptions& options = {});
// The same with each file's own options, one per path: the image size or OpenCV model one file
// needs and another holds (two opencv-kd files of their own sizes).
CameraRig readCameraRig(const std::vector<std::string>& paths, const std::vector<CameraFileOptions>& options);

}  // namespace mdbrief
