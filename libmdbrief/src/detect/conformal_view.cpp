#include "detect/conformal_view.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

namespace mdbrief::detail {
namespace {

// Stereographic coordinates of a bearing for f = 1: 2 tan(theta / 2) along the bearing's
// azimuth. tan(theta / 2) = sin(theta) / (1 + cos(theta)) needs no angle.
cv::Point2d stereographic(const cv::Vec3d& b) {
  const double n = cv::norm(b);
  const double k = 2.0 / (1.0 + b[2] / n) / n;
  return {b[0] * k, b[1] * k};
}

}  // namespace

ConformalView::ConformalView(CameraPtr camera) : camera_(std::move(camera)) {
  const cv::Size image = camera_->imageSize();
  // The field of view at f = 1, from the valid pixels on a 2-pixel grid.
  cv::Point2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (int y = 0; y < image.height; y += 2)
    for (int x = 0; x < image.width; x += 2) {
      cv::Vec3d b;
      if (!camera_->isValid({double(x), double(y)}) || !camera_->pixelToBearing({double(x), double(y)}, b)) continue;
      if (!(b[2] / cv::norm(b) > -0.99)) continue;  // the antipode is at infinity
      const cv::Point2d s = stereographic(b);
      lo.x = std::min(lo.x, s.x), lo.y = std::min(lo.y, s.y);
      hi.x = std::max(hi.x, s.x), hi.y = std::max(hi.y, s.y);
    }
  if (!(lo.x < hi.x && lo.y < hi.y)) throw std::invalid_argument("ConformalView: the camera has no valid pixel");
  const double full = camera_->tangentPlaneScale();
  const double area = (hi.x - lo.x) * (hi.y - lo.y) * full * full;
  f_ = full * std::min(1.0, std::sqrt(double(image.area()) / area));
  // View pixels share the fractional part of the optical axis' camera pixel: at zoom 1 the view
  // then samples the image centre on its own pixel grid, without interpolation blur.
  cv::Point2d axis;
  if (!camera_->bearingToPixel({0, 0, 1}, axis)) axis = {0, 0};
  origin_ = {std::floor(lo.x * f_) - 2 - (axis.x - std::floor(axis.x)), std::floor(lo.y * f_) - 2 - (axis.y - std::floor(axis.y))};
  size_ = {static_cast<int>(std::ceil(hi.x * f_ - origin_.x)) + 3, static_cast<int>(std::ceil(hi.y * f_ - origin_.y)) + 3};

  cv::Mat mapX(size_, CV_32F), mapY(size_, CV_32F), inside(size_, CV_8U);
  tbb::parallel_for(0, size_.height, [&](int v) {
    for (int u = 0; u < size_.width; ++u) {
      cv::Point2d pixel;
      const bool ok = camera_->bearingToPixel(bearing({double(u), double(v)}), pixel) && camera_->isValid(pixel);
      mapX.at<float>(v, u) = ok ? static_cast<float>(pixel.x) : -1.f;
      mapY.at<float>(v, u) = ok ? static_cast<float>(pixel.y) : -1.f;
      inside.at<uchar>(v, u) = ok ? 255 : 0;
    }
  });
  cv::convertMaps(mapX, mapY, map1_, map2_, CV_16SC2);
  // A view pixel next to an invalid one may blend in its value.
  cv::erode(inside, valid_, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
}

cv::Mat ConformalView::remap(const cv::Mat& grey) const {
  cv::Mat out;
  cv::remap(grey, out, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  return out;
}

cv::Vec3d ConformalView::bearing(const cv::Point2d& p) const {
  const double x = (p.x + origin_.x) / f_, y = (p.y + origin_.y) / f_;
  // Inverse of stereographic(): with q = (x^2 + y^2) / 4, the bearing is (x, y, 1 - q) / (1 + q).
  const double q = (x * x + y * y) / 4.0;
  return cv::Vec3d(x, y, 1.0 - q) / (1.0 + q);
}

bool ConformalView::toCamera(const cv::Point2d& p, cv::Point2d& pixel, double& scale) const {
  cv::Point2d px0, px1, py0, py1;
  if (!camera_->bearingToPixel(bearing(p), pixel) || !camera_->bearingToPixel(bearing(p - cv::Point2d(0.5, 0)), px0) ||
      !camera_->bearingToPixel(bearing(p + cv::Point2d(0.5, 0)), px1) ||
      !camera_->bearingToPixel(bearing(p - cv::Point2d(0, 0.5)), py0) ||
      !camera_->bearingToPixel(bearing(p + cv::Point2d(0, 0.5)), py1))
    return false;
  const cv::Point2d dx = px1 - px0, dy = py1 - py0;
  scale = std::sqrt(std::abs(dx.x * dy.y - dx.y * dy.x));
  return std::isfinite(scale) && scale > 0;
}

}  // namespace mdbrief::detail
