#pragma once
// The Mikolajczyk precision-recall protocol of the paper (section "Results on Real Data"):
// ground-truth correspondences by mapping keypoints through the ground-truth transform and
// taking the nearest keypoint within 3 px; brute-force nearest-neighbour matching with a
// sweeping distance threshold t; recall(t) = #correct / #ground truth,
// 1-precision(t) = #false / #matches; the mean curve over image pairs.
#include <functional>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "descriptor_method.hpp"

namespace mdbrief::eval {

// Ground-truth transform of one image pair: pixel of image a -> pixel of image b (empty when
// the point does not map, e.g. leaves the scene).
using GroundTruthMap = std::function<std::optional<cv::Point2d>(const cv::Point2d&)>;

// Nearest-neighbour matches of one pair, with their correctness.
struct PairMatches {
  std::vector<double> distance;  // per query: distance to its nearest neighbour in b
  std::vector<char> correct;     // per query: its nearest neighbour is within radius of the truth
  int groundTruth = 0;           // queries with a keypoint of b within radius of their image
};

// radius: the 3 px of the protocol.
PairMatches matchPair(const Features& a, const Features& b, const GroundTruthMap& map, double radius = 3.0);

struct PrCurve {
  std::vector<double> threshold, recall, oneMinusPrecision;
};

// Mean curve over pairs at `steps` thresholds spread evenly over [0, maxThreshold], where
// maxThreshold is the largest nearest-neighbour distance of all pairs (so the last point
// accepts every match). A pair without matches below t contributes 1-precision 0 there.
PrCurve meanCurve(const std::vector<PairMatches>& pairs, int steps = 100);

struct PrSummary {
  // Area under recall over 1-precision, from 0 to 1; the curve is continued at its final
  // recall from its last 1-precision to 1 (every method ends there when all matches count).
  double auc = 0.0;
  double recallAt01 = 0.0;  // best recall with 1-precision <= 0.1 (linear between points)
  double recallAt02 = 0.0;  // ... <= 0.2
};

PrSummary summarize(const PrCurve& curve);

// Best recall on the curve with 1-precision <= x (interpolating the crossing segment).
double recallAt(const PrCurve& curve, double x);

}  // namespace mdbrief::eval
