#pragma once
// Image sizes in error messages, as "640x480", and read back from the command line; matrices in
// error messages with their type. Internal to the build, as atomic_file.hpp.
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief::internal {

inline std::string sizeText(cv::Size size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

// "1000 x 32 CV_32F": the shape and the type, so that a matrix of the right shape and the wrong
// type is not refused as if its shape were wrong (issue 45). One channel is the depth alone.
inline std::string matrixText(const cv::Mat& m) {
  return std::to_string(m.rows) + " x " + std::to_string(m.cols) + " " +
         (m.channels() == 1 ? std::string(cv::depthToString(m.depth())) : std::string(cv::typeToString(m.type())));
}

// "640x480" as a size, each side in [1, 10^6]; none for anything else.
inline std::optional<cv::Size> parseSizeText(const std::string& text) {
  const auto side = [](const std::string& digits, int& value) {
    if (digits.empty() || digits.size() > 7 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
    value = std::stoi(digits);
    return value >= 1 && value <= 1000000;
  };
  const std::size_t x = text.find('x');
  int width = 0, height = 0;
  if (x == std::string::npos || !side(text.substr(0, x), width) || !side(text.substr(x + 1), height))
    return std::nullopt;
  return cv::Size(width, height);
}

}  // namespace mdbrief::internal
