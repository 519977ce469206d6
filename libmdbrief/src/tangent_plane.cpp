#include "mdbrief/tangent_plane.hpp"

#include <cmath>

namespace mdbrief {

bool planeToPixel(const Camera& camera, double lambda, const cv::Point2d& planePoint,
                  cv::Point2d& pixel) {
  return camera.bearingToPixel(cv::Vec3d(planePoint.x, planePoint.y, lambda), pixel);
}

std::optional<TangentPlaneFrame> tangentPlaneAt(const Camera& camera, const cv::Point2d& pixel,
                                                double maxIncidenceDeg) {
  cv::Vec3d v;
  if (!camera.pixelToBearing(pixel, v)) return std::nullopt;
  const double norm = cv::norm(v);
  if (!(norm > 0.0) || v[2] / norm < std::cos(maxIncidenceDeg * CV_PI / 180.0)) return std::nullopt;

  TangentPlaneFrame frame;
  frame.lambda = camera.tangentPlaneScale();
  frame.anchor = {frame.lambda * v[0] / v[2], frame.lambda * v[1] / v[2]};

  // Central differences with a half-unit step: plane units are about pixels, so the stencil
  // stays within the footprint of one pixel and the truncation error is negligible.
  constexpr double h = 0.5;
  cv::Point2d xp, xm, yp, ym;
  if (!planeToPixel(camera, frame.lambda, frame.anchor + cv::Point2d(h, 0), xp) ||
      !planeToPixel(camera, frame.lambda, frame.anchor - cv::Point2d(h, 0), xm) ||
      !planeToPixel(camera, frame.lambda, frame.anchor + cv::Point2d(0, h), yp) ||
      !planeToPixel(camera, frame.lambda, frame.anchor - cv::Point2d(0, h), ym))
    return std::nullopt;
  const cv::Point2d dx = (xp - xm) / (2 * h), dy = (yp - ym) / (2 * h);
  frame.jacobian = cv::Matx22d(dx.x, dy.x, dx.y, dy.y);
  if (!(std::abs(cv::determinant(frame.jacobian)) > 1e-12)) return std::nullopt;
  return frame;
}

double imageAngleToPlaneAngle(const cv::Matx22d& jacobian, double imageAngleDeg) {
  const double a = imageAngleDeg * CV_PI / 180.0;
  const cv::Vec2d d = jacobian.inv() * cv::Vec2d(std::cos(a), std::sin(a));
  return std::atan2(d[1], d[0]) * 180.0 / CV_PI;
}

}  // namespace mdbrief
