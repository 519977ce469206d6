#pragma once
// What the subcommands of mdbrief-eval share: where the data is, the opencv-doc flag, and the
// checks of cameras, images and outputs that throw InputError (exit 2).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "eval_commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "mdbrief/camera/camera.hpp"

namespace mdbrief::eval {

// MDBRIEF_DATA or ../shared/data (relative to the working directory: the scripts run from the
// repository root; an installed program is given paths).
std::string sharedData();

// --opencv-doc-dir: Debian's opencv-doc sample photos, which the default textures come from.
void addOpencvDocFlag(CLI::App* cmd, std::string& dir);

// A calibration given as one value of a flag that takes several: "file", or "file#id" for one
// camera of a rig file (the ids of --camera-id). A value that names an existing file is a path
// even when it holds a '#'.
struct CameraReference {
  std::string path, cameraId;
  // The file's stem, and "-id" for a rig's camera: the name of what it renders.
  std::string label() const;
};
CameraReference parseCameraReference(const std::string& value);
// Refuses (InputError) two values of `flag` with one label: the results name a camera by its
// label, so two files of one stem in different folders, or one file given twice, would share
// rows (issue 45). For the start of a command, before any work.
void requireDistinctLabels(const std::vector<std::string>& values, const std::string& flag);
// The file of such a value as parseCameraReference reads it, without its checks (never throws):
// for the parse-time check of the file (toolkit/input_file_flag.hpp).
std::string cameraReferencePath(const std::string& value);

// loadCamera / loadEvaluationImage, throwing InputError.
CameraPtr loadCameraOrThrow(const std::string& path, const std::string& cameraId = "");
CameraPtr loadCameraOrThrow(const CameraReference& camera);
// Adds `flag` (e.g. --camera-id), the camera of `cameraFlag`'s file that holds several.
void addCameraIdFlag(CLI::App* cmd, std::string& id, const std::string& flag = "--camera-id",
                     const std::string& cameraFlag = "--camera");
cv::Mat loadGreyOrThrow(const std::string& path);

// internal::checkOutputsApart as an InputError: no output may be an input (under any name) or
// another output; for the commands to call before the work.
void checkOutputsApart(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);

}  // namespace mdbrief::eval
