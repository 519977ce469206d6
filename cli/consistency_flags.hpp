#pragma once
// The flags `match --inliers` and `draw --matches` share to check matches: the model (--model)
// and the second image's camera (match's --camera-b, draw's --other-camera), with the rig's
// relative pose when the model is the known pose.
#include <string>

#include <CLI/CLI.hpp>

#include "cli/extraction_flags.hpp"
#include "cli/match_consistency.hpp"

namespace mdbrief::cli {

// Adds --model bound to `model` (kConsistencyModelNames).
void addModelFlag(CLI::App& cmd, std::string& model);

// The second image's calibration flags as the first's file implies them: `second` when it names
// a file; the first's file with second's camera choice when only that was given (another camera
// of a rig file: --camera-b-id cam1); otherwise none (path empty: the first's calibration).
CameraFileFlags secondCameraFlags(const CameraFileFlags& first, const CameraFileFlags& second);

// InputError when the model needs what the flags lack: a calibration for the essential matrix and
// the known pose, and a second camera for the known pose. `second` as secondCameraFlags gives it.
void checkConsistencyModel(const std::string& model, const CameraFileFlags& first, const CameraFileFlags& second);

// Sets options.knownPose (and poseSource) to the second camera's pose in the first's frame, from
// the rig file that holds both (Kalibr, basalt, ORB-SLAM3) or the two files' extrinsics (EuRoC's
// T_BS). InputError naming the file and what it lacks, as readCameraRig says it.
void setRigPose(const CameraFileFlags& first, const CameraFileFlags& second, MatchConsistencyOptions& options);

}  // namespace mdbrief::cli
