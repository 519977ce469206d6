#pragma once
// Pinhole camera with OpenCV's radial-tangential ("plumb bob") distortion on normalised
// coordinates (x, y) = (X/Z, Y/Z), r^2 = x^2 + y^2:
//   x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
//   (u, v) = (fx x_d + cx, fy y_d + cy).
// The inverse is a radial-only 1-D solve followed by 2-D Newton steps on the full model
// (converges to ~1e-12 in normalised units). Valid where the radial part r_d(r) is increasing:
// r < rMax, the first stationary point of r_d in (0, 50] (50, i.e. 88.9 degrees, if none); a
// pixel is valid when its inverse exists and lies within rMax (|m_d| < r_d(rMax) is a quick
// pre-test; the tangential terms move the exact border slightly).
#include "mdbrief/camera.hpp"
#include "mdbrief/camera_intrinsics.hpp"

namespace mdbrief {

struct RadTanParams {
  CameraIntrinsics intrinsics;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;  // finite
};

class RadTanCamera final : public Camera {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit RadTanCamera(const RadTanParams& params);

  const RadTanParams& params() const { return p_; }
  // Largest undistorted normalised radius the model inverts.
  double maxUndistortedRadius() const { return rMax_; }

  std::string modelName() const override { return "radtan"; }
  cv::Size imageSize() const override { return p_.intrinsics.size(); }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool bearingToPixel(const cv::Vec3d& bearing, cv::Point2d& pixel) const override;
  bool isValid(const cv::Point2d& pixel) const override;
  // (fx + fy) / 2, as the pinhole camera.
  double tangentPlaneScale() const override { return 0.5 * (p_.intrinsics.fx + p_.intrinsics.fy); }
  std::shared_ptr<Camera> resized(cv::Size newSize) const override;

 private:
  double radialDistorted(double r) const;       // r (1 + k1 r^2 + k2 r^4 + k3 r^6)
  double radialDistortedPrime(double r) const;
  cv::Vec2d distort(double x, double y) const;

  RadTanParams p_;
  double rMax_;
  double rdMax_;
};

}  // namespace mdbrief
