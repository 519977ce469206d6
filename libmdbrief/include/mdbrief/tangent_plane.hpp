#pragma once
// The paper's plane Pi_lambda (eqs. 8-10): a keypoint m' is lifted to its bearing v, moved to
// the normalised plane (v / v_z) and scaled by lambda, giving m_u. dBRIEF places its tests on
// this plane. This file holds that geometry and its local linearisation.
#include <optional>

#include <opencv2/core.hpp>

#include "mdbrief/camera.hpp"

namespace mdbrief {

struct TangentPlaneFrame {
  cv::Point2d anchor;     // m_u (x, y) on Pi_lambda; the plane's z is lambda
  double lambda = 0.0;
  // d pixel / d (plane x, y) at the anchor: how a small offset on Pi_lambda appears in the
  // image, in level-0 pixels per plane unit.
  cv::Matx22d jacobian;
};

// Lifts a level-0 pixel to Pi_lambda. Empty when the pixel has no bearing, when the ray is
// more than maxIncidenceDeg from the optical axis (the plane degenerates towards 90 degrees),
// or when the Jacobian cannot be evaluated (its stencil leaves the model's domain).
std::optional<TangentPlaneFrame> tangentPlaneAt(const Camera& camera, const cv::Point2d& pixel,
                                                double maxIncidenceDeg);

// Projects a point of Pi_lambda (x, y, z = lambda) to the image. False if the camera cannot.
bool planeToPixel(const Camera& camera, double lambda, const cv::Point2d& planePoint,
                  cv::Point2d& pixel);

// A direction measured in the image (degrees, cv::KeyPoint convention) expressed as an angle
// on Pi_lambda: the plane direction the Jacobian maps onto it. Identity for a pinhole camera
// with fx = fy.
double imageAngleToPlaneAngle(const cv::Matx22d& jacobian, double imageAngleDeg);

}  // namespace mdbrief
