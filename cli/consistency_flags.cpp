#include "cli/consistency_flags.hpp"

#include <filesystem>
#include <stdexcept>

#include "cli/commands.hpp"
#include "mdbrief/camera/rig.hpp"

namespace mdbrief::cli {

void addModelFlag(CLI::App& cmd, std::string& model) {
  cmd.add_option("--model", model,
                 "The model matches are checked against: auto (essential with a calibration, else a homography of "
                 "the pixels), essential (a general scene), homography (a plane or a turned camera), pose (the "
                 "relative pose of the two cameras of a rig, from its calibration)")
      ->check(CLI::IsMember(namesOf(kConsistencyModelNames)))
      ->capture_default_str();
}

CameraFileFlags secondCameraFlags(const CameraFileFlags& first, const CameraFileFlags& second) {
  if (!second.path.empty() || !second.anyGiven()) return second;
  CameraFileFlags sameFile = second;
  sameFile.path = first.path;
  if (second.format == toString(CameraFormat::Auto)) sameFile.format = first.format;
  return sameFile;
}

void checkConsistencyModel(const std::string& model, const CameraFileFlags& first, const CameraFileFlags& second) {
  const ConsistencyModel m = parseName(model, kConsistencyModelNames, "--model");
  if (first.path.empty() && (!second.path.empty() || second.anyGiven()))
    throw InputError(second.prefix + " needs " + first.prefix + " (the first image's calibration)");
  if ((m == ConsistencyModel::Essential || m == ConsistencyModel::KnownPose) && first.path.empty())
    throw InputError("--model " + model + " needs " + first.prefix + ": it is a model of calibrated cameras");
  if (m == ConsistencyModel::KnownPose && second.path.empty())
    throw InputError("--model pose needs the second camera of the rig: " + second.prefix + " FILE, or " +
                     second.prefix + "-id ID for another camera of " + first.prefix + "'s file");
}

void setRigPose(const CameraFileFlags& first, const CameraFileFlags& second, MatchConsistencyOptions& options) {
  std::error_code ec;
  const bool oneFile = std::filesystem::equivalent(first.path, second.path, ec);
  // Each file is read with its own flags (the size and model of an opencv-kd file), so that a
  // file without extrinsics is refused for that and not for a size the flags gave (issue 45).
  CameraFileOptions firstOptions = cameraFileOptions(first), secondOptions = cameraFileOptions(second);
  firstOptions.cameraId.clear();  // the rig holds every camera; the ids choose below
  secondOptions.cameraId.clear();
  try {
    if (oneFile) {
      const CameraRig rig = readCameraRig(first.path, firstOptions);
      options.knownPose = rig.relativePose(first.id, second.id);
      options.poseSource = first.path + " (" + (first.id.empty() ? "its camera" : first.id) + " and " +
                           (second.id.empty() ? "its camera" : second.id) + ")";
    } else {
      const CameraRig rig = readCameraRig(std::vector<std::string>{first.path, second.path},
                                          std::vector<CameraFileOptions>{firstOptions, secondOptions});
      options.knownPose = rig.relativePose(0, 1);
      options.poseSource = first.path + " and " + second.path;
    }
  } catch (const std::exception& e) {
    throw InputError(std::string("--model pose: ") + e.what());
  }
  if (!(cv::norm(options.knownPose->translation) > 0.0))
    throw InputError("--model pose: " + options.poseSource +
                     ": the two cameras are at one place (no baseline), so the pose checks nothing; give the rig's "
                     "other camera");
}

}  // namespace mdbrief::cli
