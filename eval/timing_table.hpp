#pragma once
// The paper's timing table (section "Extraction Speed"): detection and description in us per
// keypoint, matching in ns per descriptor pair, total = detection + description (us per
// keypoint, as the paper's table), for the detector/descriptor combinations of the paper, all
// measured in one run on the same images; medians over repeats; ratios against ORB+ORB.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::eval {

struct TimingOptions {
  int repeats = 11;
  int keypoints = 1000;  // detector budget
  std::string outDir;
};

struct TimingRow {
  std::string detector, descriptor;
  double detectionUs = 0, descriptionUs = 0, matchingNs = 0, totalUs = 0;
  double keypoints = 0;  // mean keypoints per image
};

// images: 8UC1, all of camera's size (the distorted methods need the camera).
std::vector<TimingRow> measureTimingTable(const std::vector<cv::Mat>& images, const CameraPtr& camera,
                                          const TimingOptions& options);

// timing_table.csv (with ratios to the ORB+ORB row).
void writeTimingTable(const std::vector<TimingRow>& rows, const std::string& path);

}  // namespace mdbrief::eval
