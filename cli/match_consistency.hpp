#pragma once
// Which matches between two images agree with one motion, for `draw --matches` and
// `match --inliers`: a ground-truth pixel homography when the user has one; otherwise a model on
// the matches' bearings (mdbrief/geometry/two_view.hpp), which holds for any lens: by default the
// general one, the essential matrix, when the cameras are calibrations, and a homography between
// the pixels without one; or a plane's homography, or the relative pose of a calibrated rig, when
// asked. Matches whose keypoint has no bearing count as wrong.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/base/enum_names.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief::cli {

// The model the matches are checked against (the tools' --model).
enum class ConsistencyModel {
  Auto,        // the essential matrix when the cameras are calibrations, else a homography of pixels
  Essential,   // a general scene: relative pose by RANSAC (fitEssential)
  Homography,  // a plane, or a camera that only turned (fitHomography)
  KnownPose,   // the relative pose the calibration gives, a rig's extrinsics (checkKnownPose)
};
inline constexpr EnumName<ConsistencyModel> kConsistencyModelNames[] = {{ConsistencyModel::Auto, "auto"},
                                                                        {ConsistencyModel::Essential, "essential"},
                                                                        {ConsistencyModel::Homography, "homography"},
                                                                        {ConsistencyModel::KnownPose, "pose"}};
inline std::string toString(ConsistencyModel model) { return nameOf(model, kConsistencyModelNames); }

struct MatchConsistencyOptions {
  double thresholdPx = 2.0;  // correct: the model puts the match within this many pixels (of image B)
  ConsistencyModel model = ConsistencyModel::Auto;
  bool calibrated = true;                  // false: the cameras are pixelPlaneCamera stand-ins
  std::optional<cv::Matx33d> groundTruth;  // pixel homography from image A to image B; overrides the model
  std::optional<RelativePose> knownPose;   // KnownPose: camera B's pose in A's frame (X_A = R X_B + t)
  std::string poseSource;                  // KnownPose: where the pose comes from, for the message
};

struct MatchConsistency {
  std::vector<char> correct;  // per match
  int correctCount = 0;
  std::string method;  // how `correct` was decided (the model, and why it failed), for the tools' messages
};

// A pinhole whose bearings are the pixels themselves up to a homography: without a calibration
// (brief, mbrief), a homography between these bearings is one between pixels. Centred on `size`.
CameraPtr pixelPlaneCamera(cv::Size size);

// pairs: (index into pointsA, index into pointsB). cameraA / cameraB give the bearings (the
// same camera for two images of one lens). A model that cannot be fitted (too few matches,
// degenerate ones) confirms none, and the method says why. Throws std::invalid_argument for
// KnownPose without a pose, or with a pose of no baseline.
MatchConsistency classifyMatches(const Camera& cameraA, const Camera& cameraB, const std::vector<cv::Point2f>& pointsA,
                                 const std::vector<cv::Point2f>& pointsB, const std::vector<std::pair<int, int>>& pairs,
                                 const MatchConsistencyOptions& options);

}  // namespace mdbrief::cli
