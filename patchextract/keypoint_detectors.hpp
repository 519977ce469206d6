#pragma once
// The detectors patches can be extracted at (paper: "ORB, AKAZE and SURF"), with the size each
// one's keypoints get in the patch (a patch spans `patch diameter` level-0 pixels, 31 being
// ORB's level 0: DescriptorOptions::supportScale 1).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/base/enum_names.hpp"

namespace mdbrief::train {

enum class DetectorKind { Orb, Akaze, Surf };
// The names users type (mdbrief/base/enum_names.hpp).
inline constexpr EnumName<DetectorKind> kDetectorKindNames[] = {
    {DetectorKind::Orb, "orb"}, {DetectorKind::Akaze, "akaze"}, {DetectorKind::Surf, "surf"}};
// Throws std::invalid_argument naming the accepted values.
inline DetectorKind parseDetector(const std::string& name) { return parseName(name, kDetectorKindNames, "detector"); }
inline std::string detectorName(DetectorKind kind) { return nameOf(kind, kDetectorKindNames); }

// Up to maxKeypoints keypoints of an 8UC1 image, strongest first (ties by position), each with
// position, size, orientation and response:
// - ORB: cv::ORB (8 levels, 1.2, FAST 20, patch 31: the runtime's pyramid), size 31 * 1.2^level;
// - AKAZE: cv::AKAZE defaults, size = 3 sigma (OpenCV's convention);
// - SURF: detectSurf (patchextract/surf_detector.hpp), size = 20 s.
std::vector<cv::KeyPoint> detectKeypoints(const cv::Mat& grey, DetectorKind kind, int maxKeypoints);

// Patch diameter in level-0 pixels for a keypoint: ORB and SURF: size (ORB's patch, SURF's
// descriptor window); AKAZE: 20 sigma = size * 20 / 3 (its descriptor's window), so that the
// finest scale of every detector lands near ORB's 31-pixel level-0 patch.
double patchDiameter(DetectorKind kind, const cv::KeyPoint& keypoint);

}  // namespace mdbrief::train
