#include "mdbrief/camera/double_sphere.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {

DoubleSphereCamera::DoubleSphereCamera(const DoubleSphereParams& params)
    : CameraWithIntrinsics(params, "double_sphere") {
  if (!(p_.xi > -1.0 && p_.xi <= 1.0))
    detail::throwBadParameter("double_sphere", "xi", "must be in (-1, 1]", p_.xi);
  if (!(p_.alpha >= 0.0 && p_.alpha <= 1.0))
    detail::throwBadParameter("double_sphere", "alpha", "must be in [0, 1]", p_.alpha);
  const double a = p_.alpha, xi = p_.xi;
  const double w1 = a <= 0.5 ? a / (1.0 - a) : (1.0 - a) / a;
  w2_ = (w1 + xi) / std::sqrt(2.0 * w1 * xi + xi * xi + 1.0);
}

bool DoubleSphereCamera::unprojectable(double r2) const {
  return std::isfinite(r2) && (p_.alpha <= 0.5 || r2 * (2.0 * p_.alpha - 1.0) < 1.0);
}

bool DoubleSphereCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d m = normalise(pixel);
  const double mx = m[0], my = m[1];
  const double r2 = mx * mx + my * my;
  if (!unprojectable(r2)) return false;
  const double a = p_.alpha, xi = p_.xi;
  const double mz = (1.0 - a * a * r2) / (a * std::sqrt(1.0 - (2.0 * a - 1.0) * r2) + 1.0 - a);
  const double s = (mz * xi + std::sqrt(mz * mz + (1.0 - xi * xi) * r2)) / (mz * mz + r2);
  // s (mx, my, mz) - (0, 0, xi) is already of unit length; normalise away the rounding.
  bearing = detail::normalized({s * mx, s * my, s * mz - xi});
  return true;
}

bool DoubleSphereCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  const double d1 = cv::norm(b);
  if (!(d1 > 0.0) || !(b[2] > -w2_ * d1)) return false;
  const double zs = p_.xi * d1 + b[2];
  const double d2 = std::sqrt(b[0] * b[0] + b[1] * b[1] + zs * zs);
  const double denom = p_.alpha * d2 + (1.0 - p_.alpha) * zs;
  if (!(denom > 0.0)) return false;
  const CameraIntrinsics& k = p_.intrinsics;
  pixel = {k.fx * b[0] / denom + k.cx, k.fy * b[1] / denom + k.cy};
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool DoubleSphereCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel,
                                                cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const double d1 = cv::norm(b);
  const double zs = p_.xi * d1 + b[2];
  const double d2 = std::sqrt(b[0] * b[0] + b[1] * b[1] + zs * zs);
  const double denom = p_.alpha * d2 + (1.0 - p_.alpha) * zs;
  const cv::Vec3d dZs = p_.xi / d1 * b + cv::Vec3d(0.0, 0.0, 1.0);
  const cv::Vec3d dD2 = (cv::Vec3d(b[0], b[1], 0.0) + zs * dZs) / d2;
  jacobian = detail::rationalJacobian(p_.intrinsics.fx, p_.intrinsics.fy, b, denom,
                                      p_.alpha * dD2 + (1.0 - p_.alpha) * dZs);
  return true;
}

bool DoubleSphereCamera::isValid(const cv::Point2d& pixel) const {
  if (!detail::insideImage(pixel, imageSize())) return false;
  const cv::Vec2d m = normalise(pixel);
  return unprojectable(m[0] * m[0] + m[1] * m[1]);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat doubleSphereModelFormat() {
  return {"double_sphere", {"fx", "fy", "cx", "cy", "xi", "alpha"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            const DoubleSphereParams p{readIntrinsics(r, width, height), r.number("xi"), r.number("alpha")};
            return construct<DoubleSphereCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const DoubleSphereParams& p = as<DoubleSphereCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"xi", p.xi}, {"alpha", p.alpha}});
          },
          {{"xi", "alpha"}}};
}

}  // namespace detail
}  // namespace mdbrief
