#pragma once
// Pinhole camera with OpenCV's radial-tangential ("plumb bob") distortion on normalised
// coordinates (x, y) = (X/Z, Y/Z), r^2 = x^2 + y^2, and optionally its rational radial factor
// (OpenCV's 8-coefficient model, basalt's pinhole-radtan8, COLMAP's FULL_OPENCV):
//   radial = (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6)
//   x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y
//   (u, v) = (fx x_d + cx, fy y_d + cy).
// The inverse is a radial-only 1-D solve followed by 2-D Newton steps on the full model
// (converges to ~1e-12 in normalised units). Valid where the radial part r_d(r) is increasing:
// r < rMax, the first stationary point of r_d in (0, 50] (50, i.e. 88.9 degrees, if none), and
// r <= maxRadius when that is set; a pixel is valid when its inverse exists and lies within
// rMax (|m_d| < r_d(rMax) is a quick pre-test; the tangential terms move the exact border
// slightly).
#include <memory>

#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief::detail {
class RadTanDistortion;
}

namespace mdbrief {

struct RadTanParams {
  CameraIntrinsics intrinsics;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;  // finite
  double k4 = 0.0, k5 = 0.0, k6 = 0.0;  // finite: the rational factor's denominator; 0 = polynomial model
  // Largest undistorted normalised radius |(X/Z, Y/Z)| the calibration holds for (basalt's
  // rpmax), >= 0; 0 = no limit beyond the monotonic range.
  double maxRadius = 0.0;
};

class RadTanCamera final : public CameraWithIntrinsics<RadTanCamera, RadTanParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit RadTanCamera(const RadTanParams& params);
  ~RadTanCamera() override;

  // Largest undistorted normalised radius the model inverts.
  double maxUndistortedRadius() const;

  std::string modelName() const override { return "radtan"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  std::shared_ptr<const detail::RadTanDistortion> distortion_;
};

}  // namespace mdbrief
