#include "mdbrief/camera/kannala_brandt.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {

KannalaBrandtCamera::KannalaBrandtCamera(const KannalaBrandtParams& params)
    : CameraWithIntrinsics(params, "kannala_brandt") {
  detail::requireFinite("kannala_brandt", "k1", p_.k1);
  detail::requireFinite("kannala_brandt", "k2", p_.k2);
  detail::requireFinite("kannala_brandt", "k3", p_.k3);
  detail::requireFinite("kannala_brandt", "k4", p_.k4);
  // Stop just short of pi, where the ray direction in the image plane is undefined.
  thetaMax_ = detail::firstNonIncreasing([this](double t) { return thetaDPrime(t); }, 0.0,
                                         CV_PI * (1.0 - 1e-9));
  thetaDMax_ = thetaD(thetaMax_);
}

double KannalaBrandtCamera::thetaD(double t) const {
  const double t2 = t * t;
  return t * (1.0 + t2 * (p_.k1 + t2 * (p_.k2 + t2 * (p_.k3 + t2 * p_.k4))));
}

double KannalaBrandtCamera::thetaDPrime(double t) const {
  const double t2 = t * t;
  return 1.0 + t2 * (3.0 * p_.k1 + t2 * (5.0 * p_.k2 + t2 * (7.0 * p_.k3 + t2 * 9.0 * p_.k4)));
}

bool KannalaBrandtCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d m = normalise(pixel);
  const double mx = m[0], my = m[1];
  const double rd = std::hypot(mx, my);
  if (!std::isfinite(rd) || !(rd < thetaDMax_)) return false;
  if (rd == 0.0) {
    bearing = {0.0, 0.0, 1.0};
    return true;
  }
  // Newton on the increasing thetaD over [0, thetaMax], kept inside a shrinking bracket.
  double lo = 0.0, hi = thetaMax_, t = std::min(rd, thetaMax_);
  for (int i = 0; i < 60; ++i) {
    const double f = thetaD(t) - rd;
    const double step = f / thetaDPrime(t);
    if (std::abs(step) < 1e-14) {
      t -= step;
      break;
    }
    (f > 0.0 ? hi : lo) = t;
    t -= step;
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  }
  const double s = std::sin(t) / rd;
  bearing = {mx * s, my * s, std::cos(t)};
  return true;
}

bool KannalaBrandtCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  const double r = std::hypot(b[0], b[1]);
  const double t = std::atan2(r, b[2]);
  if (!std::isfinite(t) || !(t < thetaMax_) || (r == 0.0 && !(b[2] > 0.0))) return false;
  const CameraIntrinsics& k = p_.intrinsics;
  if (r == 0.0) {
    pixel = {k.cx, k.cy};
    return true;
  }
  const double s = thetaD(t) / r;
  pixel = {k.fx * b[0] * s + k.cx, k.fy * b[1] * s + k.cy};
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);  // an infinite b[0] or b[1]: inf * 0
}

bool KannalaBrandtCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel,
                                                 cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const CameraIntrinsics& k = p_.intrinsics;
  const double r = std::hypot(b[0], b[1]);
  if (r == 0.0) {  // on the axis theta_d = r / z to first order
    jacobian = {k.fx / b[2], 0.0, 0.0, 0.0, k.fy / b[2], 0.0};
    return true;
  }
  const double t = std::atan2(r, b[2]), n2 = r * r + b[2] * b[2];
  const double s = thetaD(t) / r, tp = thetaDPrime(t);
  // s = theta_d(theta) / r with theta = atan2(r, z).
  const cv::Vec3d dTheta(b[2] / n2 * b[0] / r, b[2] / n2 * b[1] / r, -r / n2);
  const cv::Vec3d dR(b[0] / r, b[1] / r, 0.0);
  const cv::Vec3d dS = (tp * dTheta - s * dR) / r;
  jacobian = {k.fx * (s + b[0] * dS[0]), k.fx * b[0] * dS[1], k.fx * b[0] * dS[2],
              k.fy * b[1] * dS[0], k.fy * (s + b[1] * dS[1]), k.fy * b[1] * dS[2]};
  return true;
}

bool KannalaBrandtCamera::isValid(const cv::Point2d& pixel) const {
  if (!detail::insideImage(pixel, imageSize())) return false;
  const cv::Vec2d m = normalise(pixel);
  return detail::hypotBelow(m[0], m[1], thetaDMax_);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat kannalaBrandtModelFormat() {
  return {"kannala_brandt", {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            const KannalaBrandtParams p{readIntrinsics(r, width, height), r.number("k1"), r.number("k2"),
                                        r.number("k3"), r.number("k4")};
            return construct<KannalaBrandtCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const KannalaBrandtParams& p = as<KannalaBrandtCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"k1", p.k1}, {"k2", p.k2}, {"k3", p.k3}, {"k4", p.k4}});
          },
          {{"k1", "k2", "k3", "k4"}}};
}

}  // namespace detail
}  // namespace mdbrief
