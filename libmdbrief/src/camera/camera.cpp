// Camera::bearingToPixel and bearingToPixelJacobian for the rays outside the models' band
// (camera.hpp): the one place where a ray's length is taken out of the projection.
#include "mdbrief/camera/camera.hpp"

#include <algorithm>
#include <cmath>

namespace mdbrief {
namespace {

// The ray outside the band the model is given, as ray = 2^-exponent b; false for a zero ray or
// one with a NaN component (which every model refuses). A finite ray is scaled, exactly, to a
// largest component in [0.5, 1): only components below 2^-1074 of the largest may round (to a
// subnormal or zero), far below what a pixel can show. A ray with an infinite component is given
// as it is (exponent 0).
bool scaledRay(const cv::Vec3d& b, cv::Vec3d& ray, int& exponent) {
  if (std::isnan(b[0]) || std::isnan(b[1]) || std::isnan(b[2])) return false;
  const double largest = std::max({std::abs(b[0]), std::abs(b[1]), std::abs(b[2])});
  if (largest == 0.0) return false;
  exponent = 0;
  if (std::isfinite(largest)) std::frexp(largest, &exponent);
  for (int i = 0; i < 3; ++i) ray[i] = std::ldexp(b[i], -exponent);
  return true;
}

}  // namespace

bool Camera::projectScaledRay(const cv::Vec3d& bearing, cv::Point2d& pixel) const {
  cv::Vec3d ray;
  int exponent = 0;
  return scaledRay(bearing, ray, exponent) && projectRay(ray, pixel);
}

bool Camera::projectScaledRayJacobian(const cv::Vec3d& bearing, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  cv::Vec3d ray;
  int exponent = 0;
  if (!scaledRay(bearing, ray, exponent) || !projectRayJacobian(ray, pixel, jacobian)) return false;
  // pixel(b) = pixel(2^-exponent b), so d pixel / d b is 2^-exponent times the derivative at the
  // scaled ray.
  for (double& v : jacobian.val) v = std::ldexp(v, -exponent);
  return true;
}

}  // namespace mdbrief
