#include "tracker_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mdbrief::eval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Index of the keypoint of b nearest to p within `radius`, or -1.
int nearestWithin(const std::vector<cv::KeyPoint>& b, const cv::Point2d& p, double radius) {
  int best = -1;
  double bestDistance = radius;
  for (size_t j = 0; j < b.size(); ++j) {
    const double d = cv::norm(cv::Point2d(b[j].pt) - p);
    if (d <= bestDistance) best = static_cast<int>(j), bestDistance = d;
  }
  return best;
}

// The ground truth's local linear map at p (finite differences), empty near its border.
std::optional<cv::Matx22d> localJacobian(const GroundTruthMap& map, const cv::Point2d& p) {
  const double h = 1.0;
  const auto l = map(p - cv::Point2d(h, 0)), r = map(p + cv::Point2d(h, 0));
  const auto u = map(p - cv::Point2d(0, h)), d = map(p + cv::Point2d(0, h));
  if (!l || !r || !u || !d) return std::nullopt;
  const cv::Point2d dx = (*r - *l) / (2 * h), dy = (*d - *u) / (2 * h);
  return cv::Matx22d(dx.x, dy.x, dx.y, dy.y);
}

double wrapDeg(double a) {
  a = std::fmod(a, 360.0);
  if (a > 180.0) a -= 360.0;
  if (a < -180.0) a += 360.0;
  return a;
}

std::optional<cv::Vec3d> bearingOf(const Camera& camera, const cv::KeyPoint& kp) {
  cv::Vec3d f;
  if (!camera.pixelToBearing(kp.pt, f)) return std::nullopt;
  return f;
}

}  // namespace

GroundTruthGrid groundTruthGrid(const Camera& camera, const GroundTruthMap& map, cv::Size sizeA, const cv::Mat& regionA,
                                int step) {
  GroundTruthGrid g;
  for (int y = step / 2; y < sizeA.height; y += step)
    for (int x = step / 2; x < sizeA.width; x += step) {
      if (!regionA.empty() && !regionA.at<uchar>(y, x)) continue;
      const cv::Point2d pa(x, y);
      const auto pb = map(pa);
      cv::Vec3d ba, bb;
      if (!pb || !camera.pixelToBearing(pa, ba) || !camera.pixelToBearing(*pb, bb)) continue;
      const auto scale = pixelsPerRadian(camera, pa);
      if (!scale) continue;
      g.pixelA.push_back(pa);
      g.pixelB.push_back(*pb);
      g.bearingA.push_back(ba);
      g.bearingB.push_back(bb);
      g.scaleA.push_back(*scale);
    }
  return g;
}

NeighbourTable nearestNeighbourTable(const Features& query, const Features& train) {
  const int n = query.descriptors.rows, m = train.descriptors.rows;
  NeighbourTable t;
  t.best.assign(n, -1);
  t.bestDistance.assign(n, kInf);
  t.secondDistance.assign(n, kInf);
  t.bestQuery.assign(m, -1);
  std::vector<double> columnBest(m, kInf);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double d = descriptorDistance(query, i, train, j);
      if (d < t.bestDistance[i]) {
        t.secondDistance[i] = t.bestDistance[i];
        t.bestDistance[i] = d;
        t.best[i] = j;
      } else if (d < t.secondDistance[i]) {
        t.secondDistance[i] = d;
      }
      if (d < columnBest[j]) columnBest[j] = d, t.bestQuery[j] = i;
    }
  return t;
}

std::vector<std::pair<int, int>> mutualRatioMatches(const NeighbourTable& t, double ratio) {
  std::vector<std::pair<int, int>> out;
  for (size_t i = 0; i < t.best.size(); ++i) {
    const int j = t.best[i];
    if (j < 0 || t.bestQuery[j] != static_cast<int>(i)) continue;
    if (ratio < 1.0 && !(t.bestDistance[i] < ratio * t.secondDistance[i])) continue;
    out.emplace_back(static_cast<int>(i), j);
  }
  return out;
}

double averagePrecision(const PairMatches& m) {
  if (m.groundTruth == 0) return 0.0;
  std::vector<size_t> order(m.distance.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return m.distance[x] < m.distance[y]; });
  double sum = 0;
  int correct = 0;
  for (size_t k = 0; k < order.size(); ++k)
    if (m.correct[order[k]]) sum += static_cast<double>(++correct) / static_cast<double>(k + 1);
  return sum / m.groundTruth;
}

PairEvidence pairEvidence(const Features& a, const Features& b, const Camera& camera, const GroundTruthMap& map,
                          const cv::Mat& regionB, cv::Size sizeB, const TrackerOptions& o) {
  PairEvidence e;
  e.table = nearestNeighbourTable(a, b);
  for (const auto& kp : a.keypoints) e.bearingA.push_back(bearingOf(camera, kp));
  for (const auto& kp : b.keypoints) {
    e.bearingB.push_back(bearingOf(camera, kp));
    e.scaleB.push_back(pixelsPerRadian(camera, kp.pt).value_or(0.0));
  }
  e.truth.resize(a.keypoints.size());
  std::vector<double> scales, scaleErrors, angleErrors;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    const cv::Point2d p(a.keypoints[i].pt);
    e.truth[i] = map(p);
    const auto& t = e.truth[i];
    if (!t || !(t->x >= 0 && t->y >= 0 && t->x <= sizeB.width - 1 && t->y <= sizeB.height - 1)) continue;
    if (!regionB.empty() && !regionB.at<uchar>(cvRound(t->y), cvRound(t->x))) continue;
    ++e.repeatCandidates;
    const int j = nearestWithin(b.keypoints, *t, o.radiusPx);
    if (j < 0) continue;
    ++e.repeated;
    const auto jac = localJacobian(map, p);
    if (!jac) continue;
    const double scale = std::sqrt(std::abs(cv::determinant(*jac)));
    scales.push_back(scale);
    scaleErrors.push_back(std::abs(std::log2(b.keypoints[j].size / (a.keypoints[i].size * scale))));
    if (a.keypoints[i].angle >= 0 && b.keypoints[j].angle >= 0) {
      const double ra = a.keypoints[i].angle * CV_PI / 180.0;
      const cv::Vec2d expected = *jac * cv::Vec2d(std::cos(ra), std::sin(ra));
      angleErrors.push_back(std::abs(wrapDeg(b.keypoints[j].angle - std::atan2(expected[1], expected[0]) * 180.0 / CV_PI)));
    }
  }
  e.localScale = median(scales);
  e.scaleErrorLog2 = median(scaleErrors);
  e.orientationErrorDeg = median(angleErrors);
  // The protocol of precision_recall.hpp on the same nearest neighbours.
  for (size_t i = 0; i < e.table.best.size(); ++i) {
    const int j = e.table.best[i];
    if (j < 0) continue;
    const auto& t = e.truth[i];
    const bool hasGt = t && nearestWithin(b.keypoints, *t, o.radiusPx) >= 0;
    e.nearest.groundTruth += hasGt;
    e.nearest.distance.push_back(e.table.bestDistance[i]);
    e.nearest.correct.push_back(hasGt && cv::norm(cv::Point2d(b.keypoints[j].pt) - *t) <= o.radiusPx);
  }
  e.averagePrecision = averagePrecision(e.nearest);
  return e;
}

TrackerResult trackerResult(const Features& b, const PairEvidence& e, double ratio, const Camera& camera,
                            const GroundTruthGrid& grid, bool essential, const TrackerOptions& o) {
  TrackerResult r;
  std::vector<cv::Vec3d> ba, bb;
  std::vector<double> scaleB;
  for (const auto& [i, j] : mutualRatioMatches(e.table, ratio)) {
    ++r.matches;
    const auto& t = e.truth[i];
    r.correct += t && cv::norm(cv::Point2d(b.keypoints[j].pt) - *t) <= o.radiusPx;
    if (!e.bearingA[i] || !e.bearingB[j] || !(e.scaleB[j] > 0)) continue;
    ba.push_back(*e.bearingA[i]);
    bb.push_back(*e.bearingB[j]);
    scaleB.push_back(e.scaleB[j]);
  }
  r.homographyErrorPx = kInf;
  if (const auto h = fitHomography(ba, bb, o.ransac, scaleB); h.ok()) {
    r.homographyInliers = h.inlierCount;
    std::vector<double> errors;
    for (size_t k = 0; k < grid.pixelA.size(); ++k) {
      const cv::Vec3d v = h.homography * grid.bearingA[k];
      cv::Point2d p;
      errors.push_back(v.dot(grid.bearingB[k]) > 0 && camera.bearingToPixel(v, p) ? cv::norm(p - grid.pixelB[k]) : kInf);
    }
    if (!errors.empty()) r.homographyErrorPx = median(errors);
  }
  r.essentialChecked = essential;
  r.essentialErrorPx = kInf;
  if (essential && !grid.pixelA.empty()) {
    const std::vector<double> scale(ba.size(), camera.tangentPlaneScale());
    if (const auto f = fitEssential(ba, bb, o.ransac, scale); f.ok()) {
      r.essentialInliers = f.inlierCount;
      std::vector<double> errors;
      for (size_t k = 0; k < grid.pixelA.size(); ++k)
        errors.push_back(epipolarAngle(f.pose, grid.bearingA[k], grid.bearingB[k]) * grid.scaleA[k]);
      r.essentialErrorPx = median(errors);
    }
  }
  return r;
}

}  // namespace mdbrief::eval
