#include "mdbrief/camera/unified.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {

UnifiedCamera::UnifiedCamera(const UnifiedParams& params) : CameraWithIntrinsics(params, modelNameOf(params)) {
  const std::string model = modelName();
  if (!(p_.alpha >= 0.0) || !std::isfinite(p_.alpha))
    detail::throwBadParameter(model, "alpha", "must be finite and >= 0", p_.alpha);
  detail::requirePositive(model, "beta", p_.beta);
  const double a = p_.alpha;
  w_ = a <= 0.5 ? a / (1.0 - a) : (1.0 - a) / a;
}

bool UnifiedCamera::unprojectable(double r2) const {
  return std::isfinite(r2) && (p_.alpha <= 0.5 || p_.beta * r2 * (2.0 * p_.alpha - 1.0) < 1.0);
}

bool UnifiedCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d m = normalise(pixel);
  const double mx = m[0], my = m[1];
  const double r2 = mx * mx + my * my;
  if (!unprojectable(r2)) return false;
  const double a = p_.alpha, br2 = p_.beta * r2;
  // z of the ray (mx, my, z) with alpha d + (1 - alpha) z = 1: the larger root of
  // (2a - 1) z^2 + 2 (1 - a) z + a^2 beta r^2 - 1 = 0. The rationalised form is stable near
  // alpha = 0.5 but 0/0 at the edge of the image when alpha > 1, where the plain form is fine.
  const double s = std::sqrt(1.0 - (2.0 * a - 1.0) * br2);
  const double mz = a <= 1.0 ? (1.0 - a * a * br2) / (a * s + 1.0 - a)
                             : (a * s - (1.0 - a)) / (2.0 * a - 1.0);
  bearing = detail::normalized({mx, my, mz});
  return true;
}

bool UnifiedCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  const double d = std::sqrt(p_.beta * (b[0] * b[0] + b[1] * b[1]) + b[2] * b[2]);
  if (!(d > 0.0) || !(b[2] > -w_ * d)) return false;
  const double denom = p_.alpha * d + (1.0 - p_.alpha) * b[2];
  if (!(denom > 0.0)) return false;
  const CameraIntrinsics& k = p_.intrinsics;
  pixel = {k.fx * b[0] / denom + k.cx, k.fy * b[1] / denom + k.cy};
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool UnifiedCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const double d = std::sqrt(p_.beta * (b[0] * b[0] + b[1] * b[1]) + b[2] * b[2]);
  const double denom = p_.alpha * d + (1.0 - p_.alpha) * b[2];
  const cv::Vec3d dD(p_.beta * b[0] / d, p_.beta * b[1] / d, b[2] / d);
  jacobian = detail::rationalJacobian(p_.intrinsics.fx, p_.intrinsics.fy, b, denom,
                                      p_.alpha * dD + cv::Vec3d(0.0, 0.0, 1.0 - p_.alpha));
  return true;
}

bool UnifiedCamera::isValid(const cv::Point2d& pixel) const {
  if (!detail::insideImage(pixel, imageSize())) return false;
  const cv::Vec2d m = normalise(pixel);
  return unprojectable(m[0] * m[0] + m[1] * m[1]);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

// UCM and EUCM are one class and two names: UCM has no beta key (it is 1).
ModelFormat ucmModelFormat() {
  return {"ucm", {"fx", "fy", "cx", "cy", "alpha"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            const UnifiedParams p{readIntrinsics(r, width, height), r.number("alpha"), 1.0};
            return construct<UnifiedCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const UnifiedParams& p = as<UnifiedCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"alpha", p.alpha}});
          },
          {{"alpha"}}};
}

ModelFormat eucmModelFormat() {
  return {"eucm", {"fx", "fy", "cx", "cy", "alpha", "beta"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            const UnifiedParams p{readIntrinsics(r, width, height), r.number("alpha"), r.number("beta")};
            return construct<UnifiedCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const UnifiedParams& p = as<UnifiedCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"alpha", p.alpha}, {"beta", p.beta}});
          },
          {{"alpha", "beta"}}};
}

}  // namespace detail
}  // namespace mdbrief
