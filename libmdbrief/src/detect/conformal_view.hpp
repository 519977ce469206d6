#pragma once
// The camera's field of view in the stereographic projection about its optical axis,
// r = 2 f tan(theta / 2): a conformal map of the viewing sphere, so a small structure keeps its
// shape wherever the lens sees it and only its scale changes, which a scale-space detector
// absorbs (DetectorOptions::conformal). f starts at the camera's tangent-plane scale (the
// resolution at the image centre) and is reduced until the view has at most the camera image's
// pixel count, so detection costs about what it costs on the camera image.
#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief::detail {

class ConformalView {
 public:
  // Throws std::invalid_argument if the camera sees nothing (no valid pixel).
  explicit ConformalView(CameraPtr camera);

  cv::Size size() const { return size_; }
  // 255 where the view pixel and its bilinear neighbours show valid camera pixels.
  const cv::Mat& validMask() const { return valid_; }

  // The camera image (8UC1 of the camera's size) in the view: bilinear, 0 outside.
  cv::Mat remap(const cv::Mat& grey) const;

  // The unit bearing of view pixel p.
  cv::Vec3d bearing(const cv::Point2d& p) const;
  // View pixel p -> camera pixel, and the local scale there: camera pixels per view pixel (the
  // geometric mean of the two directions). False where the camera cannot project the ray.
  bool toCamera(const cv::Point2d& p, cv::Point2d& pixel, double& scale) const;

 private:
  CameraPtr camera_;
  double f_ = 0;
  cv::Point2d origin_;  // view pixel (0, 0) in stereographic coordinates
  cv::Size size_;
  cv::Mat map1_, map2_;  // cv::remap's fixed-point maps
  cv::Mat valid_;
};

}  // namespace mdbrief::detail
