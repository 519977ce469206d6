#include "precision_recall.hpp"

#include <algorithm>
#include <cmath>

namespace mdbrief::eval {

PairMatches matchPair(const Features& a, const Features& b, const GroundTruthMap& map, double radius) {
  PairMatches out;
  const auto nn = nearestNeighbours(a, b);
  std::vector<std::optional<cv::Point2d>> truth(a.keypoints.size());
  std::vector<char> hasGt(a.keypoints.size(), 0);
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    truth[i] = map(cv::Point2d(a.keypoints[i].pt));
    if (!truth[i]) continue;
    for (const auto& kp : b.keypoints)
      if (cv::norm(cv::Point2d(kp.pt) - *truth[i]) <= radius) {
        hasGt[i] = 1;
        break;
      }
    out.groundTruth += hasGt[i];
  }
  for (const auto& m : nn) {
    const auto& t = truth[m.queryIdx];
    out.distance.push_back(m.distance);
    out.correct.push_back(hasGt[m.queryIdx] && t && cv::norm(cv::Point2d(b.keypoints[m.trainIdx].pt) - *t) <= radius);
  }
  return out;
}

PrCurve meanCurve(const std::vector<PairMatches>& pairs, int steps) {
  PrCurve c;
  double maxT = 0.0;
  for (const auto& p : pairs)
    for (double d : p.distance) maxT = std::max(maxT, d);
  for (int s = 0; s <= steps; ++s) {
    const double t = maxT * s / steps;
    double recall = 0, omp = 0;
    int used = 0;
    for (const auto& p : pairs) {
      if (p.groundTruth == 0) continue;
      int matches = 0, correct = 0;
      for (size_t i = 0; i < p.distance.size(); ++i)
        if (p.distance[i] <= t) ++matches, correct += p.correct[i];
      recall += static_cast<double>(correct) / p.groundTruth;
      omp += matches ? static_cast<double>(matches - correct) / matches : 0.0;
      ++used;
    }
    c.threshold.push_back(t);
    c.recall.push_back(used ? recall / used : 0.0);
    c.oneMinusPrecision.push_back(used ? omp / used : 0.0);
  }
  return c;
}

double recallAt(const PrCurve& c, double x) {
  double best = 0.0;
  for (size_t i = 0; i < c.recall.size(); ++i) {
    if (c.oneMinusPrecision[i] <= x) best = std::max(best, c.recall[i]);
    if (i > 0) {
      const double x0 = c.oneMinusPrecision[i - 1], x1 = c.oneMinusPrecision[i];
      if ((x0 - x) * (x1 - x) < 0) {  // the segment crosses x
        const double f = (x - x0) / (x1 - x0);
        best = std::max(best, c.recall[i - 1] + f * (c.recall[i] - c.recall[i - 1]));
      }
    }
  }
  return best;
}

PrSummary summarize(const PrCurve& c) {
  PrSummary s;
  if (c.recall.empty()) return s;
  // Upper envelope as a function of 1-precision: sort the points by x, keep the running best
  // recall (a higher threshold never lowers recall, but 1-precision need not be monotone).
  std::vector<std::pair<double, double>> pts;
  for (size_t i = 0; i < c.recall.size(); ++i) pts.emplace_back(c.oneMinusPrecision[i], c.recall[i]);
  std::sort(pts.begin(), pts.end());
  double area = 0, prevX = 0, prevY = 0, best = 0;
  for (const auto& [x, y] : pts) {
    best = std::max(best, y);
    area += (x - prevX) * (prevY + best) / 2;
    prevX = x, prevY = best;
  }
  area += (1.0 - prevX) * prevY;
  s.auc = area;
  s.recallAt01 = recallAt(c, 0.1);
  s.recallAt02 = recallAt(c, 0.2);
  return s;
}

}  // namespace mdbrief::eval
