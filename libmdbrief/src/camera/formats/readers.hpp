#pragma once
// The readers of the calibration files other tools write (camera/io.hpp lists them), each in
// its own file (camera/formats/<tool>.cpp), and the helpers they share. camera/io.cpp recognises
// the format and hands the file to its reader. Every error is a std::runtime_error that starts
// with the file's path and names the key, line or value at fault.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/rig.hpp"

namespace mdbrief::detail {

class YamlReader;

// Kalibr's camera_model / distortion_model combinations (kalibr.cpp), which EuRoC's sensor.yaml
// shares: the intrinsics under "intrinsics", the coefficients under `coefficientsKey`; `tool`
// names the file's tool in the message for an unsupported combination.
std::shared_ptr<Camera> kalibrModelCamera(const YamlReader& c, const std::string& model, const std::string& distortion,
                                          cv::Size size, const std::string& coefficientsKey, const std::string& tool);

// An opencv-matrix node (rows, cols, dt, data) under `key` of r: rows x cols numbers, row-major.
std::vector<double> openCvMatrix(const YamlReader& r, const std::string& key, int& rows, int& cols);

// A rigid transform out of a row-major 4 x 4 matrix (or 3 x 4, its last row implied) under
// `key` of r: the last row must be 0 0 0 1 and the rotation orthonormal within 1e-3 (files keep
// 6 to 12 digits); it is then made exactly orthonormal. Errors name the key.
RigidTransform rigidTransformOf(const YamlReader& r, const std::string& key, const std::vector<double>& rowMajor);

// The camera `wanted` among `ids` (a file's cameras, in file order), for the error messages
// "<path>: <what> has cameras cam0, cam1: choose one" and "... has no camera 'x' (it has ...)".
// An empty `wanted` picks the only camera.
std::string chooseCamera(const std::string& path, const std::string& what, const std::vector<std::string>& ids,
                         const std::string& wanted);

// Kalibr camchain.yaml: top-level camN maps with camera_model.
bool isKalibrCamchain(const YAML::Node& root);
std::shared_ptr<Camera> readKalibrCamchain(const std::string& path, const YAML::Node& root, const std::string& camera);
std::vector<std::string> kalibrCameraIds(const YAML::Node& root);
// The first camera's (cam0's) frame is the rig's: camN through the T_cn_cnm1 chain, else
// through T_cam_imu (its own and the first camera's).
std::optional<RigidTransform> kalibrCameraToRig(const std::string& path, const YAML::Node& root, const std::string& id);

// basalt calib.json: value0 with intrinsics and resolution lists.
bool isBasaltCalibration(const YAML::Node& root);
std::shared_ptr<Camera> readBasaltCalibration(const std::string& path, const YAML::Node& root, const std::string& camera);
std::vector<std::string> basaltCameraIds(const std::string& path, const YAML::Node& root);
// The IMU's frame is the rig's: value0.T_imu_cam[index].
std::optional<RigidTransform> basaltCameraToRig(const std::string& path, const YAML::Node& root, const std::string& id);

// ORB-SLAM3 settings: Camera.type.
bool isOrbSlam3Settings(const YAML::Node& root);
std::shared_ptr<Camera> readOrbSlam3Settings(const std::string& path, const YAML::Node& root, const std::string& camera);
std::vector<std::string> orbSlam3CameraIds(const YAML::Node& root);
// Camera 1's frame is the rig's: camera 2 through Tlr (old keys) or Stereo.T_c1_c2 (File.version
// 1.0), which map camera 2's points into camera 1's.
std::optional<RigidTransform> orbSlam3CameraToRig(const std::string& path, const YAML::Node& root, const std::string& id);

// EuRoC / Kimera-VIO sensor.yaml: sensor_type, or camera_model with resolution.
bool isEurocSensor(const YAML::Node& root);
std::shared_ptr<Camera> readEurocSensor(const std::string& path, const YAML::Node& root);
// The body's frame is the rig's: T_BS.
std::optional<RigidTransform> eurocCameraToRig(const std::string& path, const YAML::Node& root);

// OpenCV FileStorage calibration (the calibration samples' output): camera_matrix.
bool isOpenCvCalibration(const YAML::Node& root);
std::shared_ptr<Camera> readOpenCvCalibration(const std::string& path, const YAML::Node& root,
                                              const CameraFileOptions& options);

// A FileStorage file with K and D (cv2.fisheye / cv2.calibrateCamera results saved as is).
bool isOpenCvKd(const YAML::Node& root);
std::shared_ptr<Camera> readOpenCvKd(const std::string& path, const YAML::Node& root, const CameraFileOptions& options);

// COLMAP cameras.txt: lines "CAMERA_ID MODEL WIDTH HEIGHT PARAMS...".
bool isColmapCameras(const std::string& text);
std::shared_ptr<Camera> readColmapCameras(const std::string& path, const std::string& text, const std::string& camera);
std::vector<std::string> colmapCameraIds(const std::string& path, const std::string& text);

}  // namespace mdbrief::detail
