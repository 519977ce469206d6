#include "mdbrief/camera/omni.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"
#include "camera/radtan_distortion.hpp"

namespace mdbrief {
namespace {
// As the radtan model's: the distortion is searched for its monotonic range up to |m| = 50.
constexpr double kRadiusSearchLimit = 50.0;
}  // namespace

OmniCamera::OmniCamera(const OmniParams& params) : CameraWithIntrinsics(params, "omni") {
  if (!(p_.xi >= 0.0) || !std::isfinite(p_.xi)) detail::throwBadParameter("omni", "xi", "must be finite and >= 0", p_.xi);
  // d|m|/dtheta = (1 + xi cos theta) / (cos theta + xi)^2: the projection turns back at
  // cos theta = -1 / xi, and the plane is reached only where cos theta > -xi.
  w_ = p_.xi <= 1.0 ? p_.xi : 1.0 / p_.xi;
  distortion_ = std::make_shared<detail::RadTanDistortion>(detail::RadTanCoefficients{p_.k1, p_.k2, p_.p1, p_.p2},
                                                           "omni", kRadiusSearchLimit);
}

OmniCamera::~OmniCamera() = default;

bool OmniCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d d = normalise(pixel);
  cv::Vec2d m;
  if (!distortion_->undistort(d[0], d[1], m)) return false;
  const double r2 = m[0] * m[0] + m[1] * m[1], xi = p_.xi;
  // The sphere point s = lambda (mx, my, 1) - (0, 0, xi) with |s| = 1: the root of
  // (1 + r2) lambda^2 - 2 xi lambda + xi^2 - 1 = 0 on the side z > -w.
  const double discriminant = 1.0 + (1.0 - xi * xi) * r2;
  if (!(discriminant >= 0.0)) return false;
  const double lambda = (xi + std::sqrt(discriminant)) / (1.0 + r2);
  const cv::Vec3d s(lambda * m[0], lambda * m[1], lambda - xi);
  if (!(s[2] > -w_)) return false;
  bearing = detail::normalized(s);
  return true;
}

bool OmniCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  const double norm = cv::norm(b);
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  const double z = b[2] / norm;
  // z > -w >= -xi keeps z + xi positive (an exact difference near the bound).
  if (!(z > -w_)) return false;
  const double denom = z + p_.xi;
  const double mx = b[0] / norm / denom, my = b[1] / norm / denom;
  if (!(std::hypot(mx, my) < distortion_->maxRadius())) return false;
  const cv::Vec2d d = distortion_->distort(mx, my);
  pixel = denormalise(d[0], d[1]);
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool OmniCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const double norm = cv::norm(b);
  const cv::Vec3d n = b / norm;
  const double denom = n[2] + p_.xi;
  const cv::Matx23d dM(1.0 / denom, 0.0, -n[0] / (denom * denom), 0.0, 1.0 / denom, -n[1] / (denom * denom));
  const cv::Matx33d dN = (cv::Matx33d::eye() - n * n.t()) * (1.0 / norm);
  const cv::Matx22d d = distortion_->jacobian(n[0] / denom, n[1] / denom);
  jacobian = detail::scaleRows(p_.intrinsics.fx, p_.intrinsics.fy, cv::Matx23d(d * dM * dN));
  return true;
}

bool OmniCamera::isValid(const cv::Point2d& pixel) const {
  // As for radtan, the inversion itself decides the border the distortion folds at.
  cv::Vec3d bearing;
  return detail::insideImage(pixel, imageSize()) && pixelToBearing(pixel, bearing);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat omniModelFormat() {
  return {"omni", {"fx", "fy", "cx", "cy", "xi", "k1", "k2", "p1", "p2"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            const OmniParams p{readIntrinsics(r, width, height), r.number("xi"), r.number("k1"), r.number("k2"),
                               r.number("p1"), r.number("p2")};
            return construct<OmniCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const OmniParams& p = as<OmniCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"xi", p.xi}, {"k1", p.k1}, {"k2", p.k2}, {"p1", p.p1}, {"p2", p.p2}});
          },
          {}};
}

}  // namespace detail
}  // namespace mdbrief
