#include "command_helpers.hpp"

#include <cstdlib>
#include <filesystem>
#include <map>

#include "eval_datasets.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "toolkit/data_folders.hpp"

namespace mdbrief::eval {

std::string sharedData() {
  if (const char* env = std::getenv("MDBRIEF_DATA"); env && *env) return env;
  return "../shared/data";
}

void addCameraIdFlag(CLI::App* cmd, std::string& id, const std::string& flag, const std::string& cameraFlag) {
  cmd->add_option(flag, id,
                  "The camera of " + cameraFlag + "'s file when it holds several (a rig): Kalibr cam0, cam1, ...; "
                  "basalt's index; ORB-SLAM3 1 or 2; COLMAP's CAMERA_ID");
}

void addOpencvDocFlag(CLI::App* cmd, std::string& dir) {
  dir = kDebianOpencvDocData;
  cmd->add_option("--opencv-doc-dir", dir,
                  "Folder of the opencv-doc sample photos the default textures come from (default: where "
                  "Debian's opencv-doc package installs them)")
      ->envname("MDBRIEF_OPENCV_DOC")
      ->capture_default_str();
}

std::string CameraReference::label() const {
  const std::string stem = std::filesystem::path(path).stem().string();
  return cameraId.empty() ? stem : stem + "-" + cameraId;
}

CameraReference parseCameraReference(const std::string& value) {
  const auto hash = value.rfind('#');
  std::error_code ec;
  if (hash == std::string::npos || std::filesystem::exists(value, ec)) return {value, ""};
  if (hash == 0 || hash + 1 == value.size())
    throw InputError(value + ": expected a calibration file, or file#id for one camera of a rig file");
  return {value.substr(0, hash), value.substr(hash + 1)};
}

void requireDistinctLabels(const std::vector<std::string>& values, const std::string& flag) {
  std::map<std::string, std::string> seen;  // label -> the value that has it
  for (const auto& value : values) {
    const std::string label = parseCameraReference(value).label();
    const auto [at, added] = seen.emplace(label, value);
    if (!added)
      throw InputError(flag + " " + at->second + " and " + value + ": both are named '" + label +
                       "' in the results; give each camera once, from files of different names");
  }
}

std::string cameraReferencePath(const std::string& value) {
  const auto hash = value.rfind('#');
  std::error_code ec;
  if (hash == std::string::npos || hash == 0 || std::filesystem::exists(value, ec)) return value;
  return value.substr(0, hash);
}

CameraPtr loadCameraOrThrow(const CameraReference& camera) {
  try {
    CameraFileOptions options;
    options.cameraId = camera.cameraId;
    return loadCamera(camera.path, options);
  } catch (const CameraIdRequired& e) {
    // Here the id is part of the value.
    throw InputError(std::string(e.what()) + " as " + camera.path + "#id");
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

CameraPtr loadCameraOrThrow(const std::string& path, const std::string& cameraId) {
  try {
    CameraFileOptions options;
    options.cameraId = cameraId;
    return loadCamera(path, options);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

cv::Mat loadGreyOrThrow(const std::string& path) {
  try {
    return loadEvaluationImage(path);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

void checkOutputsApart(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  try {
    internal::checkOutputsApart({inputs.begin(), inputs.end()}, {outputs.begin(), outputs.end()});
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace mdbrief::eval
