#pragma once
// Kannala-Brandt fisheye model as in OpenCV's cv::fisheye and Kalibr's "equidistant":
//   theta = angle between ray and optical axis,
//   theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//   (u, v) = (fx theta_d x / r + cx, fy theta_d y / r + cy),  r = sqrt(x^2 + y^2).
// The inverse solves theta_d(theta) by safeguarded Newton. Valid where theta_d is increasing:
// theta < thetaMax, the first stationary point of theta_d in (0, pi) (pi if none).
#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief {

struct KannalaBrandtParams {
  CameraIntrinsics intrinsics;
  double k1 = 0.0, k2 = 0.0, k3 = 0.0, k4 = 0.0;  // finite
};

class KannalaBrandtCamera final : public CameraWithIntrinsics<KannalaBrandtCamera, KannalaBrandtParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit KannalaBrandtCamera(const KannalaBrandtParams& params);

  // Largest angle from the optical axis (radians) the model inverts.
  double maxTheta() const { return thetaMax_; }

  std::string modelName() const override { return "kannala_brandt"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  double thetaD(double theta) const;
  double thetaDPrime(double theta) const;

  double thetaMax_;
  double thetaDMax_;  // thetaD(thetaMax_)
};

}  // namespace mdbrief
