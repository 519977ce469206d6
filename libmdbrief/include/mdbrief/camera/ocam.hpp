#pragma once
// Scaramuzza's omnidirectional model as implemented by the OCamCalib toolbox (the paper's
// fisheye model, eq. Omni). OCamCalib works in its own frame: x_o along image rows, y_o along
// columns, z_o = f(rho) = a0 + a1 rho + ... + aN rho^N with a0 < 0, so rays in front of the lens
// have z_o < 0. Its pixel mapping (cam2world / world2cam of ocam_functions.cpp) is
//   [row - v0; col - u0] = [c d; e 1] [x_o; y_o],   rho = |(x_o, y_o)|,
// and the inverse polynomial maps theta = atan(z_o / |(x_o, y_o)|) (-pi/2 on the axis) to rho.
// Our bearing frame (camera.hpp) is (X, Y, Z) = (y_o, x_o, -z_o): a proper rotation.
// bearingToPixel evaluates the inverse polynomial and refines rho with Newton steps on the
// forward polynomial, so the two directions agree to ~1e-9 px.
// Validity: rho < rhoMax, the end of the range where the elevation angle atan2(f(rho), rho)
// increases (searched up to 1.5x the largest centre-to-corner distance), and, when validRadius
// > 0, |(u - u0, v - v0)| <= validRadius (the image circle).
#include <vector>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief {

struct OcamParams {
  int width = 0;                // image size in pixels, > 0
  int height = 0;
  std::vector<double> forward;  // a0..aN (N >= 1), ascending powers of rho, OCamCalib sign: a0 < 0
  std::vector<double> inverse;  // b0..bM (M >= 1), ascending powers of theta; empty: fitted
  double c = 1.0, d = 0.0, e = 0.0;  // affine matrix [c d; e 1] on (row, column), c - d e != 0
  double u0 = 0.0;              // centre column (pixels, 0-based)
  double v0 = 0.0;              // centre row
  double validRadius = 0.0;     // image-circle radius about (u0, v0) in pixels; 0 = none
};

class OcamCamera final : public Camera {
 public:
  // Throws std::invalid_argument naming the bad parameter. An empty `inverse` is fitted by
  // least squares over the valid field of view (degree raised until the fit is within 0.05 px).
  explicit OcamCamera(const OcamParams& params);

  // The parameters, with the fitted inverse polynomial when none was given.
  const OcamParams& params() const { return p_; }
  // Largest distance from the centre (in the affine-corrected frame) the model inverts.
  double maxRho() const { return rhoMax_; }

  std::string modelName() const override { return "ocam"; }
  cv::Size imageSize() const override { return {p_.width, p_.height}; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override;
  bool isValid(const cv::Point2d& pixel) const override;
  // |a0|, the paper's lambda for the fisheye model.
  double tangentPlaneScale() const override { return std::abs(p_.forward.front()); }
  // Exact for any new size: the aspect change is absorbed into the affine matrix (c, d) and the
  // polynomials are rescaled; the image circle radius is scaled by sqrt(sx sy).
  std::shared_ptr<Camera> resized(cv::Size newSize) const override;

 private:
  bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const override;
  bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const override;

  double elevation(double rho) const;  // atan2(f(rho), rho)
  double solveRho(double norm, double zo, double rhoGuess) const;

  OcamParams p_;
  double invDet_;
  double rhoMax_;
  double thetaMax_;  // elevation(rhoMax_)
};

}  // namespace mdbrief
