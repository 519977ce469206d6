#pragma once
// Mei's unified omnidirectional model with radial-tangential distortion (Mei & Rives,
// "Single View Point Omnidirectional Camera Calibration from Planar Grids", ICRA 2007), Kalibr's
// "omni" camera with "radtan" (or "none") distortion. The ray is put on the unit sphere and
// projected from a point xi behind the sphere's centre onto the normalised plane, which is
// distorted as the radtan model's:
//   (x, y, z) = X / |X|,  m = (x, y) / (z + xi),
//   m_d = radtan(m; k1, k2, p1, p2),   (u, v) = (fx m_dx + cx, fy m_dy + cy).
// The inverse undistorts m_d (as camera/radtan.hpp) and lifts m back onto the sphere in closed
// form. Validity: rays with z > -w, w = min(xi, 1 / xi) (0 for xi = 0: the pinhole), where the
// projection is one-to-one, and |m| below the distortion's monotonic limit (first stationary
// point of the radial part in (0, 50]).
#include <memory>

#include "mdbrief/camera/with_intrinsics.hpp"

namespace mdbrief::detail {
class RadTanDistortion;
}

namespace mdbrief {

struct OmniParams {
  CameraIntrinsics intrinsics;
  double xi = 1.0;  // mirror parameter, finite and >= 0 (0: the radtan camera)
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0;  // finite
};

class OmniCamera final : public CameraWithIntrinsics<OmniCamera, OmniParams> {
 public:
  // Throws std::invalid_argument naming the bad parameter.
  explicit OmniCamera(const OmniParams& params);
  ~OmniCamera() override;

  std::string modelName() const override { return "omni"; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;
  // (fx + fy) / 2 / (1 + xi): the local scale at the image centre (Kalibr's omni focal lengths
  // are about twice a fisheye's for xi near 1).
  double tangentPlaneScale() const override { return 0.5 * (p_.intrinsics.fx + p_.intrinsics.fy) / (1.0 + p_.xi); }

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  double w_;  // rays with z > -w_ (on the unit sphere) project one-to-one
  std::shared_ptr<const detail::RadTanDistortion> distortion_;
};

}  // namespace mdbrief
