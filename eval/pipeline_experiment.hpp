#pragma once
// Whole pipelines at equal keypoint budgets (issue 10, item 3): each detector on its own
// keypoints with its descriptor, scored by repeatability (detector only) and by the paper's PR
// protocol (detector + descriptor). Writes pipelines_summary.csv.
#include <string>
#include <vector>

#include "descriptor_method.hpp"
#include "pr_experiment.hpp"

namespace mdbrief::eval {

struct PipelineSpec {
  std::string name;       // label, "<detector>+<descriptor>"
  KeypointSource detector;
  MethodSpec descriptor;  // described on the detector's keypoints
};

// modORB with mdBRIEF / dBRIEF / BRIEF-256; cv::ORB, AKAZE, BRISK and SIFT each with its own
// descriptor; mdBRIEF-256 on AKAZE's and SIFT's keypoints at the support scales chosen in
// docs/RESULTS.md "Descriptor footprint for other detectors".
std::vector<PipelineSpec> standardPipelines();

struct PipelineOptions {
  std::string outDir;
  std::vector<int> budgets{500, 1000};
  double radiusPx = 3.0;
  int curveSteps = 100;
  DetectorOptions library;  // the library's detectors (method and nfeatures are set per pipeline)
};

// Repeatability of one pair: of the keypoints of `a` whose true position in `b` lies inside
// `bSize` (and inside `bMask` when not empty), the fraction that have a keypoint of `b` within
// `radius`. Returns {repeated, candidates}.
std::pair<int, int> repeatedKeypoints(const std::vector<cv::KeyPoint>& a, const std::vector<cv::KeyPoint>& b,
                                      const GroundTruthMap& map, cv::Size bSize, const cv::Mat& bMask,
                                      double radius);

void runPipelines(const std::vector<EvalGroup>& groups, const std::vector<PipelineSpec>& pipelines,
                  const PipelineOptions& options);

}  // namespace mdbrief::eval
