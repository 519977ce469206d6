#pragma once
// Guided matching: each query is compared only with the train keypoints within a radius of the
// position predicted for it in the train image (a tracker's motion model, a projected map
// point), the search by projection of feature-based SLAM. The train keypoints are put into a
// grid of uniform cells about the radius wide, once per call, so a query visits only the cells
// its window overlaps.
//
// The distance, the ratio test and the mutual check are those of matcher.hpp restricted to the
// windows: a query's two nearest are taken among its candidates, and the mutual check asks that
// the query be the train's nearest among the queries whose windows contain that train. Hence a
// match the brute-force matcher keeps is kept here too whenever the query's prediction lies in
// the image and its train within the radius of it (and, with the consistency checks on, passes
// them): fewer candidates only loosen both tests.
//
// Results are deterministic and independent of threading: ties go to the lowest train index
// (mutual check: the lowest query index), whatever the order of the grid's cells.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/types.hpp>

#include "mdbrief/match/matcher.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {

struct GuidedMatchOptions {
  // Search radius in pixels of the train image: a train keypoint is a candidate of a query if
  // its position lies within this distance of the query's prediction (a disc, border
  // included). Must be in [0, 10000]; 0 keeps only keypoints exactly at the prediction.
  // Default 15 px, the window ORB-SLAM's monocular motion-model search uses at the finest
  // scale; the benchmark uses it with predictions up to 10 px off.
  float radius = 15.f;
  // Orientation consistency: keep a candidate only if its angle and the query keypoint's differ
  // by at most this many degrees (on the circle, so 359 and 1 differ by 2). In (0, 180]; unset
  // (default) = off. Needs the query and train keypoints' angles (cv::KeyPoint::angle, >= 0).
  std::optional<float> maxAngleDifference;
  // Scale consistency: keep a candidate only if the larger of the two keypoints' sizes is at
  // most this many times the smaller (cv::KeyPoint::size, which grows with the pyramid octave,
  // so the ratio bounds the octave difference too: scaleFactor^k for k octaves). In [1, 1000];
  // unset (default) = off. Needs both keypoints' sizes (> 0).
  std::optional<float> maxScaleRatio;
  // Ratio test, mutual check, distance bound and threading, as for brute force (matcher.hpp),
  // with the same defaults.
  MatchOptions matching;
};

// The fields of GuidedMatchOptions (option_fields.hpp); MatchOptions' fields as "matching.*".
const OptionTable<GuidedMatchOptions>& guidedMatchOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const GuidedMatchOptions& options);

// One match per query that passes the enabled tests, in query order, as matchBruteForce gives
// them (queryIdx, trainIdx, distance in bits, imgIdx = 0).
//   query:          N x bytes CV_8UC1 descriptors (as matchBruteForce).
//   queryKeypoints: the queries' keypoints, N of them, or none (empty) when neither consistency
//                   check is on: only their angle and size are read.
//   predicted:      N positions in the train image; one outside [0, width) x [0, height) or not
//                   finite has no candidates (no prediction), so it gives no match.
//   train, trainKeypoints: M descriptors and their M keypoints (position; angle and size for
//                   the checks). A train position must be finite; it may lie outside the image.
//   imageSize:      the train image's size (width and height >= 1), which the grid covers.
// Throws std::invalid_argument naming the argument for a mismatch of sizes, descriptors the
// brute-force matcher refuses, an invalid option (OptionError), or a keypoint a check needs
// without an angle or size.
std::vector<cv::DMatch> matchGuided(cv::InputArray query, const std::vector<cv::KeyPoint>& queryKeypoints,
                                    const std::vector<cv::Point2f>& predicted, cv::InputArray train,
                                    const std::vector<cv::KeyPoint>& trainKeypoints, cv::Size imageSize,
                                    const GuidedMatchOptions& options = {});

// The same with the masked Hamming distance (masked_hamming.hpp): queryMasks and trainMasks
// have the sizes of query and train (CV_8UC1).
std::vector<cv::DMatch> matchGuidedMasked(cv::InputArray query, cv::InputArray queryMasks,
                                          const std::vector<cv::KeyPoint>& queryKeypoints,
                                          const std::vector<cv::Point2f>& predicted, cv::InputArray train,
                                          cv::InputArray trainMasks, const std::vector<cv::KeyPoint>& trainKeypoints,
                                          cv::Size imageSize, const GuidedMatchOptions& options = {});

}  // namespace mdbrief
