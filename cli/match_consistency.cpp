#include "cli/match_consistency.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief::cli {

CameraPtr pixelPlaneCamera(cv::Size size) {
  // Any focal length gives the same homography test; the width keeps angles moderate.
  CameraIntrinsics k;
  k.width = size.width, k.height = size.height;
  k.fx = k.fy = std::max(1, size.width);
  k.cx = 0.5 * (size.width - 1), k.cy = 0.5 * (size.height - 1);
  return std::make_shared<PinholeCamera>(k);
}

MatchConsistency classifyMatches(const Camera& cameraA, const Camera& cameraB, const std::vector<cv::Point2f>& pointsA,
                                 const std::vector<cv::Point2f>& pointsB, const std::vector<std::pair<int, int>>& pairs,
                                 const MatchConsistencyOptions& options) {
  MatchConsistency out;
  out.correct.assign(pairs.size(), 0);
  std::ostringstream method;
  if (options.groundTruth) {
    method << "ground-truth homography, " << options.thresholdPx << " px";
    const cv::Matx33d& h = *options.groundTruth;
    for (size_t k = 0; k < pairs.size(); ++k) {
      const cv::Point2f a = pointsA[pairs[k].first], b = pointsB[pairs[k].second];
      const cv::Vec3d p = h * cv::Vec3d(a.x, a.y, 1.0);
      if (!(std::abs(p[2]) > 1e-12)) continue;
      out.correct[k] = std::hypot(p[0] / p[2] - b.x, p[1] / p[2] - b.y) <= options.thresholdPx;
      out.correctCount += out.correct[k];
    }
    out.method = method.str();
    return out;
  }
  std::vector<cv::Vec3d> a, b;
  std::vector<double> scale;
  std::vector<size_t> used;  // match of each fitted correspondence
  for (size_t k = 0; k < pairs.size(); ++k) {
    const cv::Point2d pa = pointsA[pairs[k].first], pb = pointsB[pairs[k].second];
    cv::Vec3d ba, bb;
    const auto s = pixelsPerRadian(cameraB, pb);
    if (!s || !cameraA.pixelToBearing(pa, ba) || !cameraB.pixelToBearing(pb, bb)) continue;
    a.push_back(ba), b.push_back(bb), scale.push_back(*s), used.push_back(k);
  }
  TwoViewOptions twoView;
  twoView.maxPixels = options.thresholdPx;
  ConsistencyModel model = options.model;
  if (model == ConsistencyModel::Auto) model = options.calibrated ? ConsistencyModel::Essential : ConsistencyModel::Homography;
  TwoViewResult fit;
  switch (model) {
    case ConsistencyModel::Essential:
      method << "essential matrix on bearings, RANSAC";
      fit = fitEssential(a, b, twoView, scale);
      break;
    case ConsistencyModel::Homography:
      method << (options.calibrated ? "homography on bearings, RANSAC" : "homography on pixels (no calibration), RANSAC");
      fit = fitHomography(a, b, twoView, scale);
      break;
    case ConsistencyModel::KnownPose:
      if (!options.knownPose) throw std::invalid_argument("the known-pose check needs a relative pose");
      method << "known relative pose" << (options.poseSource.empty() ? "" : " of " + options.poseSource);
      fit = checkKnownPose(a, b, *options.knownPose, twoView, scale);
      break;
    case ConsistencyModel::Auto:
      break;
  }
  method << ", " << options.thresholdPx << " px";
  if (!fit.ok()) method << ": " << fit.reason << ", none confirmed";
  out.method = method.str();
  if (!fit.ok()) return out;
  for (size_t i = 0; i < used.size(); ++i) out.correct[used[i]] = fit.inliers[i];
  out.correctCount = fit.inlierCount;
  return out;
}

}  // namespace mdbrief::cli
