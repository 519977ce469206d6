#pragma once
// Round-trip measurements shared by the camera tests.
#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::testing {

struct RoundTripStats {
  int valid = 0;             // grid points (or bearings) that took part
  int total = 0;             // grid points (or bearings) tried
  int failed = 0;            // valid points whose round trip returned false
  double maxError = 0.0;     // pixels (pixel round trip) or radians (bearing round trip)
};

// pixel -> bearing -> pixel over a grid of step `step` px covering the image, on the pixels
// the camera calls valid.
inline RoundTripStats pixelRoundTrip(const Camera& camera, double step) {
  RoundTripStats s;
  const cv::Size size = camera.imageSize();
  for (double v = 0.0; v <= size.height - 1.0; v += step)
    for (double u = 0.0; u <= size.width - 1.0; u += step) {
      ++s.total;
      const cv::Point2d p(u, v);
      if (!camera.isValid(p)) continue;
      ++s.valid;
      cv::Vec3d b;
      cv::Point2d q;
      if (!camera.pixelToBearing(p, b) || !camera.bearingToPixel(b, q)) {
        ++s.failed;
        continue;
      }
      s.maxError = std::max(s.maxError, cv::norm(q - p));
    }
  return s;
}

inline double angleBetween(const cv::Vec3d& a, const cv::Vec3d& b) {
  return std::atan2(cv::norm(a.cross(b)), a.dot(b));
}

// bearing -> pixel -> bearing over directions spread on the sphere (polar angle up to 180
// degrees in `rings` rings); bearings whose pixel is not valid are skipped.
inline RoundTripStats bearingRoundTrip(const Camera& camera, int rings = 300, int perRing = 300) {
  RoundTripStats s;
  for (int i = 0; i < rings; ++i) {
    const double theta = CV_PI * (i + 0.5) / rings;
    for (int j = 0; j < perRing; ++j) {
      const double phi = 2.0 * CV_PI * j / perRing;
      const cv::Vec3d b(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                        std::cos(theta));
      ++s.total;
      cv::Point2d p;
      if (!camera.bearingToPixel(b, p) || !camera.isValid(p)) continue;
      ++s.valid;
      cv::Vec3d back;
      if (!camera.pixelToBearing(p, back)) {
        ++s.failed;
        continue;
      }
      s.maxError = std::max(s.maxError, angleBetween(b, back));
    }
  }
  return s;
}

}  // namespace mdbrief::testing
