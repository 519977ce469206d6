#pragma once
// Which matches between two images agree with one motion, for `draw --matches` and
// `match --inliers`: a ground-truth pixel homography when the user has one, otherwise the robust
// plane-induced homography between the matches' bearings (mdbrief/geometry/two_view.hpp), which
// holds for any lens. Matches whose keypoint has no bearing count as wrong.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::cli {

struct MatchConsistencyOptions {
  double thresholdPx = 2.0;               // correct: the model puts the match within this many pixels
  std::optional<cv::Matx33d> groundTruth;  // pixel homography from image A to image B
};

struct MatchConsistency {
  std::vector<char> correct;  // per match
  int correctCount = 0;
  std::string method;  // how `correct` was decided, for the tools' messages
};

// A pinhole whose bearings are the pixels themselves up to a homography: without a calibration
// (brief, mbrief), a homography between these bearings is one between pixels. Centred on `size`.
CameraPtr pixelPlaneCamera(cv::Size size);

// pairs: (index into pointsA, index into pointsB). cameraA / cameraB give the bearings (the
// same camera for two images of one lens).
MatchConsistency classifyMatches(const Camera& cameraA, const Camera& cameraB, const std::vector<cv::Point2f>& pointsA,
                                 const std::vector<cv::Point2f>& pointsB, const std::vector<std::pair<int, int>>& pairs,
                                 const MatchConsistencyOptions& options);

}  // namespace mdbrief::cli
