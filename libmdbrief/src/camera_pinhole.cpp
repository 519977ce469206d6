#include "mdbrief/camera_pinhole.hpp"

#include "camera_model_utils.hpp"

namespace mdbrief {

PinholeCamera::PinholeCamera(const CameraIntrinsics& intrinsics) : k_(intrinsics) {
  validateIntrinsics(k_, "pinhole");
}

bool PinholeCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return false;
  bearing = detail::normalized({(pixel.x - k_.cx) / k_.fx, (pixel.y - k_.cy) / k_.fy, 1.0});
  return true;
}

bool PinholeCamera::bearingToPixel(const cv::Vec3d& b, cv::Point2d& pixel) const {
  // Rays at or behind the image plane have no perspective image.
  if (!(b[2] > 0.0)) return false;
  pixel = {k_.fx * (b[0] / b[2]) + k_.cx, k_.fy * (b[1] / b[2]) + k_.cy};
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool PinholeCamera::bearingToPixelJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!bearingToPixel(b, pixel)) return false;
  jacobian = detail::scaleRows(k_.fx, k_.fy, detail::perspectiveJacobian(b));
  return true;
}

bool PinholeCamera::isValid(const cv::Point2d& pixel) const {
  return detail::insideImage(pixel, k_.size());
}

std::shared_ptr<Camera> PinholeCamera::resized(cv::Size newSize) const {
  return std::make_shared<PinholeCamera>(resizeIntrinsics(k_, newSize));
}

}  // namespace mdbrief
