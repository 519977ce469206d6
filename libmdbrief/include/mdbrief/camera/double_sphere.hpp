#pragma once
// Double sphere model (Usenko, Demmel, Cremers, "The Double Sphere Camera Model", 3DV 2018):
//   d1 = |X|,  d2 = sqrt(x^2 + y^2 + (xi d1 + z)^2),
//   (u, v) = (fx x, fy y) / (alpha d2 + (1 - alpha)(xi d1 + z)) + (cx, cy).
// Closed-form inverse. Validity (from the paper): rays with z > -w2 d1, where
//   w1 = alpha / (1 - alpha) if alpha <= 0.5 else (1 - alpha) / alpha,
//   w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1);
// pixels with r^2 = mx^2 + my^2 < 1 / (2 alpha - 1) when alpha > 0.5 (mx = (u - cx) / fx, ...).
// tangentPlaneScale() is (fx + fy) / 2. At the image centre the local scale is f / (1 + xi) for
// this model; the focal length is kept so that all perspective-family models share one definition.
#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief {

struct DoubleSphereParams {
  CameraIntrinsics intrinsics;
  double xi = 0.0;     // in (-1, 1]
  double alpha = 0.5;  // in [0, 1]
};

class DoubleSphereCamera final : public CameraWithIntrinsics<DoubleSphereCamera, DoubleSphereParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit DoubleSphereCamera(const DoubleSphereParams& params);

  std::string modelName() const override { return "double_sphere"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  bool unprojectable(double r2) const;

  double w2_;
};

}  // namespace mdbrief
