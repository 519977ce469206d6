#include "detect/orientation.hpp"

#include <cmath>

namespace mdbrief::detail {

IntensityCentroid::IntensityCentroid(int radius) : radius_(radius), halfWidth_(radius + 1) {
  // Integer disc u^2 + v^2 <= r^2; exact in integers so it is symmetric under 90° rotations.
  for (int v = 0; v <= radius; ++v) {
    int hw = 0;
    while ((hw + 1) * (hw + 1) + v * v <= radius * radius) ++hw;
    halfWidth_[v] = hw;
  }
}

float IntensityCentroid::angleDegrees(const cv::Mat& image, int x, int y) const {
  long long m10 = 0, m01 = 0;
  for (int v = -radius_; v <= radius_; ++v) {
    const uchar* row = image.ptr<uchar>(y + v) + x;
    const int hw = halfWidth_[v < 0 ? -v : v];
    long long rowSum = 0;
    for (int u = -hw; u <= hw; ++u) {
      m10 += u * row[u];
      rowSum += row[u];
    }
    m01 += v * rowSum;
  }
  if (m10 == 0 && m01 == 0) return 0.f;
  double degrees = std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * 180.0 / CV_PI;
  if (degrees < 0) degrees += 360.0;
  // atan2 of a tiny negative y gives -0 .. -epsilon, which can round up to exactly 360.
  const auto angle = static_cast<float>(degrees);
  return angle >= 360.f ? 0.f : angle;
}

}  // namespace mdbrief::detail
