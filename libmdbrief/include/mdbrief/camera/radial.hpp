#pragma once
// Pinhole camera with the paper's one-parameter radial distortion (eq. radialDistModel, the
// division model of Lourenco et al.):
//   m_d = 2 m / (1 + sqrt(1 - 4 xi |m|^2)),   inverse  m = m_d / (1 + xi |m_d|^2).
// Units of m: m = (x/z, y/z) * fx / unitPx, i.e. for square pixels the undistorted pixel offset
// from the principal point measured in units of unitPx pixels (default 100 px). Expressing m
// through the normalised coordinates keeps resized() exact for any aspect change.
// With the paper's xi = -2^-6 on the 754x480 example (fx = fy = 377.75, principal point
// (379.98, 242.82); configs/cameras/radial_example.yaml) this is a clear barrel distortion:
// the image corner (0, 0) sees the ray a pinhole would image 210 px further out, and a point
// whose undistorted image is at that corner is displaced 91.2 px towards the centre
// (tests/test_camera_models.cpp checks these numbers).
// Validity: xi < 0 (barrel) maps every ray with z > 0 inside radius |m_d| < 1/sqrt(-xi);
// xi > 0 (pincushion) needs 1 - 4 xi |m|^2 > 0, i.e. |m_d| < 1/sqrt(xi). Pixels beyond these
// radii have no inverse. xi = 0 is exactly the pinhole camera.
#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief {

struct RadialParams {
  CameraIntrinsics intrinsics;
  double xi = 0.0;       // distortion coefficient, finite; < 0 barrel, > 0 pincushion
  double unitPx = 100.0; // pixels per unit of m (along u), > 0
};

class RadialCamera final : public CameraWithIntrinsics<RadialCamera, RadialParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit RadialCamera(const RadialParams& params);

  std::string modelName() const override { return "radial"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;
  // Also rescales unitPx, so that m stays the same function of the ray.
  std::shared_ptr<Camera> resized(cv::Size newSize) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  // |m|^2 of normalised coordinates (x, y).
  double unitRadius2(double x, double y) const;
  // True when the distorted normalised point has an inverse (inside the limit radius).
  bool invertible(double xd, double yd) const;

  double mPerNormalised_;  // fx / unitPx
};

}  // namespace mdbrief
