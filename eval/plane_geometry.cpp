#include "plane_geometry.hpp"

#include <cmath>

namespace mdbrief::eval {

std::optional<cv::Point2d> pixelToPlane(const Camera& camera, const CameraPose& pose, const cv::Point2d& pixel) {
  cv::Vec3d b;
  if (!camera.pixelToBearing(pixel, b)) return std::nullopt;
  const cv::Vec3d d = pose.rotation.t() * b;
  if (d[2] == 0.0) return std::nullopt;
  const double lambda = -pose.centre[2] / d[2];
  if (!(lambda > 0.0)) return std::nullopt;
  return cv::Point2d(pose.centre[0] + lambda * d[0], pose.centre[1] + lambda * d[1]);
}

bool onTexture(const PlaneScene& scene, const cv::Point2d& p) {
  const double hw = scene.texture.cols * scene.texelSize / 2.0, hh = scene.texture.rows * scene.texelSize / 2.0;
  return std::abs(p.x) < hw && std::abs(p.y) < hh;
}

cv::Matx33d cameraRotation(double yawDeg, double pitchDeg, double rollDeg) {
  const double y = yawDeg * CV_PI / 180, p = pitchDeg * CV_PI / 180, r = rollDeg * CV_PI / 180;
  // Camera axes turned by yaw (towards +x), then pitch, then roll; world -> camera is the
  // transpose of the camera-to-world rotation Ry * Rx * Rz.
  const cv::Matx33d ry(std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y));
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(p), -std::sin(p), 0, std::sin(p), std::cos(p));
  const cv::Matx33d rz(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
  return (ry * rx * rz).t();
}

cv::Matx33d planeBearingHomography(const CameraPose& a, const CameraPose& b) {
  // A plane point (x, y, 0) has the camera ray R (X - C) = R [e1 e2 -C] (x, y, 1)^T.
  const auto planeToRay = [](const CameraPose& p) {
    return p.rotation * cv::Matx33d(1, 0, -p.centre[0], 0, 1, -p.centre[1], 0, 0, -p.centre[2]);
  };
  return planeToRay(b) * planeToRay(a).inv();
}

}  // namespace mdbrief::eval
