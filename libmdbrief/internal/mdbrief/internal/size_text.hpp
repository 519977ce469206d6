#pragma once
// Image sizes in error messages, as "640x480". Internal to the build, as atomic_file.hpp.
#include <string>

#include <opencv2/core/types.hpp>

namespace mdbrief::internal {

inline std::string sizeText(cv::Size size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

}  // namespace mdbrief::internal
