#pragma once
// Homography files as the Oxford affine sequences ship them (H1to2p...) and the evaluation's user
// data uses them: nine numbers, row by row, separated by white space.
#include <filesystem>

#include <opencv2/core/matx.hpp>

namespace mdbrief {

// Throws std::runtime_error naming the file when it cannot be opened, does not hold exactly nine
// finite numbers (white space around them only) or holds a singular matrix (all zero, say).
cv::Matx33d readHomography(const std::filesystem::path& path);

// Writes h in that form (17 significant digits, one row per line), atomically. Throws
// std::runtime_error naming the file on failure.
void writeHomography(const std::filesystem::path& path, const cv::Matx33d& h);

}  // namespace mdbrief
