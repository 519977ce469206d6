#pragma once
// Exact ground truth of the rendered-plane scenes: a pixel of one view -> the plane point it
// sees -> its pixel in another view, and the camera poses of the experiments.
#include <optional>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::eval {

// The plane point (world z = 0) seen at `pixel`; empty if the ray misses the plane.
std::optional<cv::Point2d> pixelToPlane(const Camera& camera, const CameraPose& pose, const cv::Point2d& pixel);

// True when the plane point lies on the texture itself (not its mirrored continuation).
bool onTexture(const PlaneScene& scene, const cv::Point2d& planeXY);

// Rotation about the camera's own axes (degrees): yaw about y, pitch about x, roll about the
// optical axis z; the result maps world to camera as CameraPose::rotation.
cv::Matx33d cameraRotation(double yawDeg, double pitchDeg, double rollDeg);

// The homography between bearings that the plane z = 0 induces: bearing_b ~ H * bearing_a
// with a positive factor for plane points in front of both cameras; det(H) > 0 when both
// centres lie on the same side of the plane.
cv::Matx33d planeBearingHomography(const CameraPose& a, const CameraPose& b);

}  // namespace mdbrief::eval
