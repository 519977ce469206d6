#pragma once
// Ideal perspective camera: u = fx x/z + cx, v = fy y/z + cy. Projects only rays with z > 0.
#include "mdbrief/camera.hpp"
#include "mdbrief/camera_intrinsics.hpp"

namespace mdbrief {

class PinholeCamera final : public Camera {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit PinholeCamera(const CameraIntrinsics& intrinsics);

  const CameraIntrinsics& intrinsics() const { return k_; }

  std::string modelName() const override { return "pinhole"; }
  cv::Size imageSize() const override { return k_.size(); }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool bearingToPixel(const cv::Vec3d& bearing, cv::Point2d& pixel) const override;
  bool bearingToPixelJacobian(const cv::Vec3d& bearing, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;
  bool isValid(const cv::Point2d& pixel) const override;
  // (fx + fy) / 2: the mean focal length, so non-square pixels get the average footprint.
  double tangentPlaneScale() const override { return 0.5 * (k_.fx + k_.fy); }
  std::shared_ptr<Camera> resized(cv::Size newSize) const override;

 private:
  CameraIntrinsics k_;
};

}  // namespace mdbrief
