#pragma once
// The plane dBRIEF places its tests on at a keypoint, scaled by lambda (Camera::
// tangentPlaneScale, so that plane units are about pixels at the image centre):
// - Local (DistortionForm::Affine): the plane tangent to the viewing sphere at the keypoint's
//   ray, spanned by the camera's x and y axes turned by the rotation that takes the optical axis
//   to the ray. It is what a perspective camera pointed at the keypoint would see: the lens'
//   distortion is removed and no perspective stretch is added, so a turned camera sees the same
//   footprint on a structure wherever the lens sees it, at any incidence (docs/RESULTS.md
//   "Real images: what a tracker keeps", the turned-lens photos).
// - Global (DistortionForm::Paper): the paper's Pi_lambda (eqs. 8-10), the plane z = lambda for
//   every keypoint (m_u = lambda v / v_z). Off the axis it stretches a structure radially by
//   1 / cos^2 of the incidence, and it degenerates towards 90 degrees.
// This file holds that geometry and its local linearisation.
#include <optional>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief {

struct TangentPlaneFrame {
  // The plane point at offset (x, y) from the keypoint is origin + x e1 + y e2; a ray through it
  // is the point itself.
  cv::Vec3d origin;       // the keypoint on the plane (local: lambda times its unit ray)
  cv::Vec3d e1, e2;       // the plane's unit axes
  double lambda = 0.0;
  // d pixel / d (plane x, y) at the keypoint: how a small offset on the plane appears in the
  // image, in level-0 pixels per plane unit.
  cv::Matx22d jacobian;
};

// The frame at a level-0 pixel, local or global (see above). Empty when the pixel has no bearing,
// when its ray is more than maxIncidenceDeg from the optical axis (the global plane needs less
// than 90), or when the camera cannot project the ray back (Camera::bearingToPixelJacobian).
std::optional<TangentPlaneFrame> tangentPlaneAt(const Camera& camera, const cv::Point2d& pixel,
                                                double maxIncidenceDeg, bool local = true);

// Projects the plane point at `offset` (plane units) from the keypoint to the image. False if
// the camera cannot.
bool planeToPixel(const Camera& camera, const TangentPlaneFrame& frame, const cv::Point2d& offset,
                  cv::Point2d& pixel);

// A direction measured in the image (degrees, cv::KeyPoint convention) expressed as an angle
// on the plane: the plane direction the Jacobian maps onto it. Identity for a pinhole camera
// with fx = fy at its centre.
double imageAngleToPlaneAngle(const cv::Matx22d& jacobian, double imageAngleDeg);

}  // namespace mdbrief
