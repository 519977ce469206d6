#pragma once
// The tracker benchmark's real 3D set (docs/RESULTS.md "Real stereo: poses against the known
// pose"): the stereo pairs of ../shared/data/stereo (EuRoC V1_01, radial-tangential, 19 pairs; a
// MYNT EYE fisheye pair), whose calibration files give each camera's pose. Every match is
// labelled by the known relative pose (its epipolar plane, in front of both cameras), not by a
// homography: rooms are not planes. Per pipeline and ratio: right matches per pair and their
// precision, the right matches' distance from their epipolar planes in pixels (median, 90th
// percentile), and the relative pose that the library's fitEssential gives on the matches'
// bearings, scored by its angular error against the known pose (AUC at 5, 10 and 20 degrees).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mdbrief/camera/rig.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "tracker_experiment.hpp"

namespace mdbrief::eval {

struct StereoPair {
  std::string left, right;  // image files, or names of rendered images
  cv::Mat leftImage, rightImage;  // rendered pairs: the images themselves (files are read otherwise)
  // Rendered pairs: the pose of b in a's frame, and where a pixel of a lies in b (exact).
  std::optional<RelativePose> pose;
  std::function<std::optional<cv::Point2d>(const cv::Point2d&)> truthInB;
};

// One stereo camera and its pairs.
struct StereoSet {
  std::string name;  // "euroc-v1-01", "mynteye-fisheye", "rendered-rig"
  CameraPtr left, right;
  RelativePose pose;  // of the right camera in the left's frame, unless a pair has its own
  std::vector<StereoPair> pairs;
};

// The sets found under `data`/stereo (the data folder of ../shared). Throws std::runtime_error
// naming the file at fault; an empty list when the folder is missing.
std::vector<StereoSet> loadStereoSets(const std::string& data);

// A stereo rig of `camera` rendered in a textured box room (scenes/room_renderer.hpp; the
// opencv-doc photos on its walls, from `opencvDocDir`): four side-by-side pairs with an exact
// pose and an exact position in b of every pixel of a. Throws std::runtime_error naming a photo
// that cannot be read.
StereoSet renderedStereoRig(const std::string& opencvDocDir, const CameraPtr& camera);

struct StereoOptions {
  int budget = 1000;  // keypoints per image, each pipeline its own
  // The ratio sweep; 1 = mutual nearest neighbours without a ratio test.
  std::vector<double> ratios{0.6, 0.7, 0.8, 0.9, 1.0};
  double rightPx = 2.0;             // a match is right within this distance of its epipolar plane (pixels of b)
  double residualRatio = 0.8;       // the ratio the residual's figures are taken at
  TwoViewOptions fit;               // fitEssential's options (its maxPixels threshold: 2 px)
  // Library pipelines (name prefixes) also scored with their matches refined (refineMatches),
  // as a tracker uses them: a row "NAME + refine" after the pipeline's own.
  std::vector<std::string> refined{"mdbrief tracking (defaults)"};
  MatchRefinementOptions refinement;
  // Also write stereo_matches.csv, every right match at residualRatio (both bearings, b's pixels
  // per radian, its signed residual), and stereo_poses.csv, each pair's known pose: what a check
  // of the pose itself needs (scripts/stereo_pose_check.py).
  bool writeMatches = false;
};

// The figures of one set, pipeline and ratio.
struct StereoSummary {
  std::string set, pipeline;
  double ratio = 0;
  int pairs = 0;
  double keypoints = 0, matchesPerPair = 0, rightPerPair = 0, precision = 0;
  double residualMedianPx = 0, residualP90Px = 0;  // over the right matches at this ratio
  // Their mean signed distance from the epipolar plane (the side of b's normal, E^T a): near 0
  // when the known pose is right, whatever the matches' precision; a pose off by a small turn
  // moves every match to one side.
  double residualSignedMeanPx = 0;
  double fitsOk = 0;                               // share of pairs whose fit succeeded
  double auc5 = 0, auc10 = 0, auc20 = 0;           // pose error max(rotation, translation direction)
  double medianPoseErrorDeg = 0;                   // +inf when half the fits failed
  double medianRotationErrorDeg = 0;               // the rotation's error alone
  // Rendered pairs: the distance of the right matches (within 3 px of the truth) from where a's
  // point truly lies in b, root mean square over all, and per level of b's keypoint (its octave
  // for the library; empty for OpenCV's pipelines, whose octaves mean other scales).
  // The residual's median and 90th percentile over a band of right matches: by quarter of b's
  // keypoint size (fromSize: the quarter's smallest size) and by b's pyramid level.
  struct Band {
    float fromSize = 0;
    double medianPx = 0, p90Px = 0;
    int count = 0;
  };
  std::vector<Band> residualBySizeQuarter, residualByLevel;
  double localisationRmsPx = 0;
  std::vector<double> localisationRmsPerLevel;
  std::vector<int> rightPerLevel;
};

// Area under the recall curve of pose errors up to `limit` degrees, divided by `limit` (a failed
// fit's error is +inf): 1 when every error is 0.
double poseAuc(std::vector<double> errorsDeg, double limit);

// Runs every pipeline on every pair of every set; writes stereo_pairs.csv and stereo_summary.csv
// (and with writeMatches stereo_matches.csv and stereo_poses.csv) into outDir and prints each
// pipeline at the ratio of its best AUC at 5 degrees (its own ratio for a library preset).
// Returns every row of the summary.
std::vector<StereoSummary> runStereo(const std::vector<StereoSet>& sets, const std::vector<TrackerPipeline>& pipelines,
                                     const StereoOptions& options, const std::string& outDir);

}  // namespace mdbrief::eval
