#pragma once
// What a tracker keeps of one image pair (docs/RESULTS.md "Real images: what a tracker keeps"):
// mutual nearest neighbours that pass a ratio test (masked distance where there are masks), how
// many of them are correct and their precision, and whether a robust two-view fit on their
// bearings puts the scene where the ground truth does. Next to them the descriptor's average
// precision and what explains a failed fit (repeatability, scale and orientation of the
// repeated keypoints).
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "descriptor_method.hpp"
#include "mdbrief/geometry/two_view.hpp"
#include "precision_recall.hpp"

namespace mdbrief::eval {

// Ground-truth correspondences of a pair on a grid of image a (every `step` pixels inside
// `regionA`, when not empty, where the map holds): the points a fitted model must carry to
// their true positions. Bearings and the pixel scale of a are kept for the fits' checks.
struct GroundTruthGrid {
  std::vector<cv::Point2d> pixelA, pixelB;
  std::vector<cv::Vec3d> bearingA, bearingB;
  std::vector<double> scaleA;  // pixels per radian at pixelA
};
GroundTruthGrid groundTruthGrid(const Camera& camera, const GroundTruthMap& map, cv::Size sizeA, const cv::Mat& regionA,
                                int step = 8);

// The two nearest train rows of every query row and the nearest query row of every train row,
// by the method's distance (descriptorDistance); ties go to the lowest index.
struct NeighbourTable {
  std::vector<int> best;                // per query; -1 when train is empty
  std::vector<double> bestDistance;
  std::vector<double> secondDistance;   // +inf when train has one row
  std::vector<int> bestQuery;           // per train row; -1 when query is empty
};
NeighbourTable nearestNeighbourTable(const Features& query, const Features& train);

// Mutual nearest neighbours with best < ratio * second (ratio >= 1 keeps every mutual pair):
// (query row, train row) pairs in query order.
std::vector<std::pair<int, int>> mutualRatioMatches(const NeighbourTable& table, double ratio);

// Average precision of nearest-neighbour matching: the queries' nearest neighbours ranked by
// distance, precision at each correct one summed and divided by the queries that have a
// ground-truth counterpart. 0 when none has.
double averagePrecision(const PairMatches& matches);

struct TrackerOptions {
  double radiusPx = 3.0;  // a match or a repeated keypoint is correct within this distance
  TwoViewOptions ransac;  // the fits' threshold: maxPixels (the pixels per radian of each match are given)
};

// One pair as a method sees it, independent of the ratio.
struct PairEvidence {
  PairMatches nearest;                       // nearest neighbour per query: distance, correct
  NeighbourTable table;
  std::vector<std::optional<cv::Point2d>> truth;  // per query: its true position in b
  // Per keypoint: its bearing (a, b) and the pixels per radian at it (b); empty where the camera
  // has none.
  std::vector<std::optional<cv::Vec3d>> bearingA, bearingB;
  std::vector<double> scaleB;
  int repeated = 0, repeatCandidates = 0;    // keypoints of a with a keypoint of b within the radius
  double averagePrecision = 0;
  double localScale = 0;                     // median scale change of the ground truth at the repeated keypoints
  double scaleErrorLog2 = 0;                 // median |log2(size_b / (size_a * local scale))| over repeated pairs
  double orientationErrorDeg = 0;            // median angle error of the repeated pairs
};

// camera: the sequence's camera (bearings, local scales); regionB: where b's keypoints can be
// (empty: everywhere).
PairEvidence pairEvidence(const Features& a, const Features& b, const Camera& camera, const GroundTruthMap& map,
                          const cv::Mat& regionB, cv::Size sizeB, const TrackerOptions& options);

struct TrackerResult {
  int matches = 0, correct = 0;
  // Homography between bearings: inliers and the median pixel error of the grid under the fit
  // (+inf without a fit).
  int homographyInliers = 0;
  double homographyErrorPx = 0;
  // Essential matrix (essentialChecked): inliers and the median epipolar distance of the grid
  // in pixels of image a (+inf without a fit).
  bool essentialChecked = false;
  int essentialInliers = 0;
  double essentialErrorPx = 0;
};

// The matches a tracker keeps at `ratio` and the homography fit on them; with `essential` also
// the essential-matrix fit.
TrackerResult trackerResult(const Features& b, const PairEvidence& evidence, double ratio, const Camera& camera,
                            const GroundTruthGrid& grid, bool essential, const TrackerOptions& options);

}  // namespace mdbrief::eval
