#pragma once
// The checks of descriptor and mask arguments that the brute-force matcher (matcher.cpp) and the
// guided matcher (guided_matcher.cpp) share, so both refuse the same inputs with the same
// message. Internal linkage, as query_row.hpp.
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

#include "mdbrief/match/hamming.hpp"

namespace mdbrief {
namespace {

// query and train: descriptor matrices (validateDescriptorMatrix) of the same width.
inline void checkDescriptorPair(const cv::Mat& query, const cv::Mat& train) {
  validateDescriptorMatrix(query, "query");
  validateDescriptorMatrix(train, "train");
  if (!query.empty() && !train.empty() && query.cols != train.cols) {
    throw std::invalid_argument("train: width " + std::to_string(train.cols) + " bytes differs from query's " +
                                std::to_string(query.cols));
  }
}

// Masks of the descriptors' size, CV_8UC1.
inline void checkMasks(const cv::Mat& masks, const cv::Mat& desc, const char* name, const char* descName) {
  if (masks.empty() && desc.empty()) return;  // 0x0 and 0 x bytes both mean "no descriptors"
  if (masks.size() != desc.size()) {
    throw std::invalid_argument(std::string(name) + ": size " + std::to_string(masks.rows) + "x" +
                                std::to_string(masks.cols) + " differs from " + descName + "'s " +
                                std::to_string(desc.rows) + "x" + std::to_string(desc.cols));
  }
  if (masks.type() != CV_8UC1) {
    throw std::invalid_argument(std::string(name) + ": masks must be CV_8UC1, got " + cv::typeToString(masks.type()));
  }
}

}  // namespace
}  // namespace mdbrief
