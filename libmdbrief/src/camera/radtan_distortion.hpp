#pragma once
// OpenCV's radial-tangential distortion of normalised coordinates (x, y), r^2 = x^2 + y^2, with
// the rational radial factor of its 8-coefficient model (basalt's pinhole-radtan8, COLMAP's
// FULL_OPENCV):
//   radial = (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6)
//   x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2),  y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y.
// Shared by the models that distort a normalised plane (radtan: the pinhole's, omni: the unit
// sphere's). With k4 = k5 = k6 = 0 the denominator is exactly 1, so every value is bit for bit
// the polynomial model's.
#include <opencv2/core.hpp>

namespace mdbrief::detail {

struct RadTanCoefficients {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0, k4 = 0.0, k5 = 0.0, k6 = 0.0;
};

class RadTanDistortion {
 public:
  // `model` names the camera model in errors; throws std::invalid_argument for a non-finite
  // coefficient. The invertible range ends at the first stationary point of the radial part
  // r * radial(r^2) in (0, searchLimit] (or where its denominator reaches 0), and at limit when
  // limit > 0.
  RadTanDistortion(const RadTanCoefficients& c, const char* model, double searchLimit, double limit = 0.0);

  const RadTanCoefficients& coefficients() const { return c_; }
  // Largest undistorted radius the model inverts, and its distorted radius.
  double maxRadius() const { return rMax_; }
  double maxDistortedRadius() const { return rdMax_; }

  cv::Vec2d distort(double x, double y) const;
  // d distort / d (x, y) (symmetric).
  cv::Matx22d jacobian(double x, double y) const;
  // The undistorted point of (xd, yd) within maxRadius(), or false (no inverse there).
  bool undistort(double xd, double yd, cv::Vec2d& undistorted) const;

 private:
  double radial(double r2) const;
  double radialDistorted(double r) const;       // r * radial(r^2)
  double radialDistortedPrime(double r) const;  // its derivative; NaN where the denominator is <= 0

  RadTanCoefficients c_;
  double rMax_;
  double rdMax_;
};

}  // namespace mdbrief::detail
