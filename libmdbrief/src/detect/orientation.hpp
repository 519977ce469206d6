#pragma once
// ORB's intensity-centroid orientation (Rosin): the angle of the vector from the keypoint to
// the centroid of the intensities in a disc around it.
#include <vector>

#include <opencv2/core.hpp>

namespace mdbrief::detail {

class IntensityCentroid {
 public:
  explicit IntensityCentroid(int radius);

  // Angle in degrees in [0, 360), measured from +x towards +y (image axes, y down, as
  // cv::KeyPoint::angle); 0 for a patch without a centroid offset. The caller guarantees
  // radius() pixels of image around (x, y).
  float angleDegrees(const cv::Mat& image, int x, int y) const;

  int radius() const { return radius_; }

 private:
  int radius_;
  std::vector<int> halfWidth_;  // halfWidth_[|v|]: the disc's row v spans u in [-hw, hw]
};

}  // namespace mdbrief::detail
