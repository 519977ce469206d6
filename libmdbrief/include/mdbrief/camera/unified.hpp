#pragma once
// Unified camera model (UCM) and extended unified camera model (EUCM, Khomutenko et al. 2016)
// in the alpha parametrisation used by basalt and fisheye-calib-adapter:
//   d = sqrt(beta (x^2 + y^2) + z^2),
//   (u, v) = (fx x, fy y) / (alpha d + (1 - alpha) z) + (cx, cy).
// UCM is EUCM with beta = 1 (its xi = alpha / (1 - alpha)). Closed-form inverse.
// Validity: rays with z > -w d, w = alpha / (1 - alpha) if alpha <= 0.5 else (1 - alpha) / alpha;
// pixels with beta r^2 < 1 / (2 alpha - 1) when alpha > 0.5 (r^2 = mx^2 + my^2, mx = (u-cx)/fx).
// alpha > 1 is accepted (fisheye-calib-adapter's UCM.yml has alpha = 1.017): w is then negative,
// i.e. the field of view is below 180 degrees, and the conditions above still hold.
#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief {

struct UnifiedParams {
  CameraIntrinsics intrinsics;
  double alpha = 0.5;  // >= 0; alpha = 0 is the pinhole camera
  double beta = 1.0;   // > 0; exactly 1 for UCM
};

class UnifiedCamera final : public CameraWithIntrinsics<UnifiedCamera, UnifiedParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit UnifiedCamera(const UnifiedParams& params);

  // "ucm" when beta == 1 (the two models are then identical), "eucm" otherwise.
  std::string modelName() const override { return modelNameOf(p_); }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  bool unprojectable(double r2) const;

  static std::string modelNameOf(const UnifiedParams& params) { return params.beta == 1.0 ? "ucm" : "eucm"; }

  double w_;
};

}  // namespace mdbrief
