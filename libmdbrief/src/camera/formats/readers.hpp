#pragma once
// The readers of the calibration files other tools write (camera/io.hpp lists them), each in
// its own file (camera/formats/<tool>.cpp), and the helpers they share. camera/io.cpp recognises
// the format and hands the file to its reader. Every error is a std::runtime_error that starts
// with the file's path and names the key, line or value at fault.
#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::detail {

// The camera `wanted` among `ids` (a file's cameras, in file order), for the error messages
// "<path>: <what> has cameras cam0, cam1: choose one" and "... has no camera 'x' (it has ...)".
// An empty `wanted` picks the only camera.
std::string chooseCamera(const std::string& path, const std::string& what, const std::vector<std::string>& ids,
                         const std::string& wanted);

// Kalibr camchain.yaml: top-level camN maps with camera_model.
bool isKalibrCamchain(const YAML::Node& root);
std::shared_ptr<Camera> readKalibrCamchain(const std::string& path, const YAML::Node& root, const std::string& camera);

// basalt calib.json: value0 with intrinsics and resolution lists.
bool isBasaltCalibration(const YAML::Node& root);
std::shared_ptr<Camera> readBasaltCalibration(const std::string& path, const YAML::Node& root, const std::string& camera);

// ORB-SLAM3 settings: Camera.type.
bool isOrbSlam3Settings(const YAML::Node& root);
std::shared_ptr<Camera> readOrbSlam3Settings(const std::string& path, const YAML::Node& root, const std::string& camera);

// OpenCV FileStorage calibration (the calibration samples' output): camera_matrix.
bool isOpenCvCalibration(const YAML::Node& root);
std::shared_ptr<Camera> readOpenCvCalibration(const std::string& path, const YAML::Node& root);

// COLMAP cameras.txt: lines "CAMERA_ID MODEL WIDTH HEIGHT PARAMS...".
bool isColmapCameras(const std::string& text);
std::shared_ptr<Camera> readColmapCameras(const std::string& path, const std::string& text, const std::string& camera);

}  // namespace mdbrief::detail
