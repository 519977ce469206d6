#pragma once
// Ideal perspective camera: u = fx x/z + cx, v = fy y/z + cy. Projects only rays with z > 0.
#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief {

// Its parameters are the intrinsics alone: params() and intrinsics() are the same.
class PinholeCamera final : public CameraWithIntrinsics<PinholeCamera, CameraIntrinsics> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit PinholeCamera(const CameraIntrinsics& intrinsics);

  std::string modelName() const override { return "pinhole"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;
};

}  // namespace mdbrief
