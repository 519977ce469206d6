#include "mdbrief/camera/tangent_plane.hpp"

#include <cmath>

namespace mdbrief {

bool planeToPixel(const Camera& camera, const TangentPlaneFrame& frame, const cv::Point2d& offset,
                  cv::Point2d& pixel) {
  return camera.bearingToPixel(frame.origin + frame.e1 * offset.x + frame.e2 * offset.y, pixel);
}

std::optional<TangentPlaneFrame> tangentPlaneAt(const Camera& camera, const cv::Point2d& pixel,
                                                double maxIncidenceDeg, bool local) {
  cv::Vec3d v;
  if (!camera.pixelToBearing(pixel, v)) return std::nullopt;
  const double norm = cv::norm(v);
  if (!(norm > 0.0)) return std::nullopt;
  const cv::Vec3d ray = v / norm;
  // The global plane meets rays in front of the camera only.
  if (ray[2] < std::cos(maxIncidenceDeg * CV_PI / 180.0) || (!local && !(ray[2] > 0.0))) return std::nullopt;

  TangentPlaneFrame frame;
  frame.lambda = camera.tangentPlaneScale();
  if (local) {
    frame.origin = ray * frame.lambda;
    // Rodrigues' rotation about z x ray by the incidence: the axes stay those of the image at
    // the centre and turn continuously with the ray (undefined only straight behind the lens).
    const cv::Vec3d axis(-ray[1], ray[0], 0.0);
    const double s = cv::norm(axis), c = ray[2];
    if (s < 1e-12) {
      if (c < 0) return std::nullopt;
      frame.e1 = {1, 0, 0};
      frame.e2 = {0, 1, 0};
    } else {
      const cv::Vec3d k = axis / s;
      const auto turn = [&](const cv::Vec3d& x) { return x * c + k.cross(x) * s + k * (k.dot(x) * (1.0 - c)); };
      frame.e1 = turn({1, 0, 0});
      frame.e2 = turn({0, 1, 0});
    }
  } else {
    frame.origin = cv::Vec3d(ray[0], ray[1], ray[2]) * (frame.lambda / ray[2]);
    frame.e1 = {1, 0, 0};
    frame.e2 = {0, 1, 0};
  }

  // The plane point at (x, y) is origin + x e1 + y e2: its image moves by d pixel / d bearing
  // times e1 and e2.
  cv::Point2d centre;
  cv::Matx23d projection;
  if (!camera.bearingToPixelJacobian(frame.origin, centre, projection)) return std::nullopt;
  frame.jacobian =
      projection * cv::Matx32d(frame.e1[0], frame.e2[0], frame.e1[1], frame.e2[1], frame.e1[2], frame.e2[2]);
  if (!(std::abs(cv::determinant(frame.jacobian)) > 1e-12)) return std::nullopt;
  return frame;
}

double imageAngleToPlaneAngle(const cv::Matx22d& jacobian, double imageAngleDeg) {
  const double a = imageAngleDeg * CV_PI / 180.0;
  const cv::Vec2d d = jacobian.inv() * cv::Vec2d(std::cos(a), std::sin(a));
  return std::atan2(d[1], d[0]) * 180.0 / CV_PI;
}

}  // namespace mdbrief
