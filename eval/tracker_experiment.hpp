#pragma once
// The tracker benchmark (docs/RESULTS.md "Real images: what a tracker keeps"): every pipeline on
// its own keypoints, every pair of every data set, scored by what a tracker keeps at each ratio
// of a sweep (tracker_metrics.hpp). Writes tracker_pairs.csv (one row per pair, pipeline and
// ratio) and tracker_summary.csv (per data set, pipeline and ratio), and prints the table of
// each pipeline at its ratio: the one it ships with, or the best of the sweep.
#include <optional>
#include <string>
#include <vector>

#include "mdbrief/api/feature2d.hpp"
#include "pr_experiment.hpp"
#include "tracker_metrics.hpp"

namespace mdbrief::eval {

struct TrackerPipeline {
  enum class Kind { Library, Orb, Akaze, Sift, Brisk };
  std::string name;
  Kind kind = Kind::Library;
  MdBriefOptions options;        // Library: detector and descriptor (nfeatures is the budget)
  // The ratio its user is told to use (a library preset's); empty: the best of the sweep.
  std::optional<double> ratio;
};

// The library's presets (tracking = create()'s defaults, matching, paper) at their own ratios,
// the defaults with the random test set, and cv::ORB, AKAZE, SIFT and BRISK each with its own
// detector and descriptor.
std::vector<TrackerPipeline> standardTrackerPipelines();

// The pipeline's keypoints (at most `budget`, inside `region` when not empty) and descriptors.
Features trackerFeatures(const TrackerPipeline& pipeline, const cv::Mat& image, const CameraPtr& camera,
                         const cv::Mat& region, int budget);

struct TrackerExperimentOptions {
  std::string outDir;
  int budget = 500;
  // The ratio sweep; 1 = mutual nearest neighbours without a ratio test.
  std::vector<double> ratios{0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 1.0};
  int gridStep = 8;  // ground-truth grid of the fit check, pixels
  TrackerOptions tracker;
};

// Which ratio of the sweep a pipeline without its own is shown at: the most right fits (3 px),
// then the most within 1 px, then the most correct matches.
struct TrackerSummary {
  std::string group, pipeline;
  double ratio = 0;
  int pairs = 0;
  double meanAp = 0, prAuc = 0, repeatability = 0;
  double correctPerPair = 0, precision = 0;
  double homographyRight3 = 0, homographyRight1 = 0, homographyInliers = 0;
  bool essential = false;
  double essentialRight3 = 0, essentialRight1 = 0, essentialInliers = 0;
  double keypoints = 0;
};

// Runs every pipeline on every group; returns the rows of the printed table.
std::vector<TrackerSummary> runTracker(const std::vector<EvalGroup>& groups,
                                       const std::vector<TrackerPipeline>& pipelines,
                                       const TrackerExperimentOptions& options);

}  // namespace mdbrief::eval
