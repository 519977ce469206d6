#include "mdbrief/camera/radial.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {

RadialCamera::RadialCamera(const RadialParams& params) : CameraWithIntrinsics(params, "radial") {
  detail::requireFinite("radial", "xi", p_.xi);
  detail::requirePositive("radial", "unit_px", p_.unitPx);
  mPerNormalised_ = p_.intrinsics.fx / p_.unitPx;
}

double RadialCamera::unitRadius2(double x, double y) const {
  return (x * x + y * y) * mPerNormalised_ * mPerNormalised_;
}

bool RadialCamera::invertible(double xd, double yd) const {
  // |xi m_d^2| < 1 covers both signs: the denominator 1 + xi |m_d|^2 stays positive (xi < 0)
  // and the division model stays monotonic (xi > 0).
  return std::abs(p_.xi * unitRadius2(xd, yd)) < 1.0;
}

bool RadialCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d m = normalise(pixel);
  const double xd = m[0], yd = m[1];
  if (!std::isfinite(xd) || !std::isfinite(yd) || !invertible(xd, yd)) return false;
  const double s = 1.0 / (1.0 + p_.xi * unitRadius2(xd, yd));
  bearing = detail::normalized({xd * s, yd * s, 1.0});
  return true;
}

bool RadialCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  if (!(b[2] > 0.0)) return false;
  const double x = b[0] / b[2], y = b[1] / b[2];
  const double disc = 1.0 - 4.0 * p_.xi * unitRadius2(x, y);
  if (!(disc > 0.0)) return false;  // beyond the pincushion model's range
  // Scale factor of eq. radialDistModel; exactly 1 for xi = 0 so the model equals the pinhole.
  const double s = 2.0 / (1.0 + std::sqrt(disc));
  pixel = denormalise(x * s, y * s);
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool RadialCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const double x = b[0] / b[2], y = b[1] / b[2];
  const double q = std::sqrt(1.0 - 4.0 * p_.xi * unitRadius2(x, y));
  const double s = 2.0 / (1.0 + q);
  // ds / d(x^2 + y^2), the unit radius being (x^2 + y^2) m^2.
  const double dS = 4.0 * p_.xi / (q * (1.0 + q) * (1.0 + q)) * mPerNormalised_ * mPerNormalised_;
  const cv::Matx22d normalised(s + 2.0 * x * x * dS, 2.0 * x * y * dS, 2.0 * x * y * dS, s + 2.0 * y * y * dS);
  jacobian = detail::scaleRows(p_.intrinsics.fx, p_.intrinsics.fy,
                               cv::Matx23d(normalised * detail::perspectiveJacobian(b)));
  return true;
}

bool RadialCamera::isValid(const cv::Point2d& pixel) const {
  if (!detail::insideImage(pixel, imageSize())) return false;
  const cv::Vec2d m = normalise(pixel);
  return invertible(m[0], m[1]);
}

std::shared_ptr<Camera> RadialCamera::resized(cv::Size newSize) const {
  RadialParams r = resizedParams(newSize);
  r.unitPx = p_.unitPx * r.intrinsics.fx / p_.intrinsics.fx;  // keeps m per normalised unit
  return std::make_shared<RadialCamera>(r);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat radialModelFormat() {
  return {"radial", {"fx", "fy", "cx", "cy", "xi", "unit_px"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            RadialParams p;
            p.intrinsics = readIntrinsics(r, width, height);
            p.xi = r.number("xi");
            p.unitPx = r.number("unit_px", p.unitPx);
            return construct<RadialCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const RadialParams& p = as<RadialCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"xi", p.xi}, {"unit_px", p.unitPx}});
          },
          {}};
}

}  // namespace detail
}  // namespace mdbrief
