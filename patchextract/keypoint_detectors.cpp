#include "patchextract/keypoint_detectors.hpp"

#include <algorithm>
#include <stdexcept>

#include <opencv2/features2d.hpp>

#include "patchextract/surf_detector.hpp"

namespace mdbrief::train {

std::vector<cv::KeyPoint> detectKeypoints(const cv::Mat& grey, DetectorKind kind, int maxKeypoints) {
  std::vector<cv::KeyPoint> kps;
  switch (kind) {
    case DetectorKind::Orb:
      cv::ORB::create(maxKeypoints)->detect(grey, kps);
      break;
    case DetectorKind::Akaze:
      cv::AKAZE::create()->detect(grey, kps);
      break;
    case DetectorKind::Surf: {
      SurfOptions o;
      o.maxKeypoints = maxKeypoints;
      kps = detectSurf(grey, o);
      break;
    }
  }
  // A total order, so the later selection does not depend on the detector's output order.
  std::sort(kps.begin(), kps.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    if (a.response != b.response) return a.response > b.response;
    if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
    if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
    return a.size < b.size;
  });
  if (static_cast<int>(kps.size()) > maxKeypoints) kps.resize(maxKeypoints);
  return kps;
}

double patchDiameter(DetectorKind kind, const cv::KeyPoint& keypoint) {
  return kind == DetectorKind::Akaze ? keypoint.size * 20.0 / 3.0 : keypoint.size;
}

}  // namespace mdbrief::train
