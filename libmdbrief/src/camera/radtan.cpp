#include "mdbrief/camera/radtan.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"
#include "camera/radtan_distortion.hpp"

namespace mdbrief {
namespace {
// Beyond ~89 degrees from the axis a pinhole-based model is meaningless anyway.
constexpr double kRadiusSearchLimit = 50.0;
}  // namespace

RadTanCamera::RadTanCamera(const RadTanParams& params) : CameraWithIntrinsics(params, "radtan") {
  if (!(p_.maxRadius >= 0.0) || !std::isfinite(p_.maxRadius))
    detail::throwBadParameter("radtan", "max_radius", "must be finite and >= 0", p_.maxRadius);
  distortion_ = std::make_shared<detail::RadTanDistortion>(
      detail::RadTanCoefficients{p_.k1, p_.k2, p_.p1, p_.p2, p_.k3, p_.k4, p_.k5, p_.k6}, "radtan",
      kRadiusSearchLimit, p_.maxRadius);
}

RadTanCamera::~RadTanCamera() = default;

double RadTanCamera::maxUndistortedRadius() const { return distortion_->maxRadius(); }

bool RadTanCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const cv::Vec2d d = normalise(pixel);
  cv::Vec2d m;
  if (!distortion_->undistort(d[0], d[1], m)) return false;
  bearing = detail::normalized({m[0], m[1], 1.0});
  return true;
}

bool RadTanCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  if (!(b[2] > 0.0)) return false;
  const double x = b[0] / b[2], y = b[1] / b[2];
  if (!(std::hypot(x, y) < distortion_->maxRadius())) return false;
  const cv::Vec2d d = distortion_->distort(x, y);
  pixel = denormalise(d[0], d[1]);
  return true;
}

bool RadTanCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const cv::Matx22d d = distortion_->jacobian(b[0] / b[2], b[1] / b[2]);
  jacobian = detail::scaleRows(p_.intrinsics.fx, p_.intrinsics.fy, cv::Matx23d(d * detail::perspectiveJacobian(b)));
  return true;
}

bool RadTanCamera::isValid(const cv::Point2d& pixel) const {
  // Near the limit the tangential terms decide whether the inverse stays inside rMax, so the
  // test is the inversion itself (no closed form for the folded region).
  cv::Vec3d bearing;
  return detail::insideImage(pixel, imageSize()) && pixelToBearing(pixel, bearing);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat radTanModelFormat() {
  return {"radtan", {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "max_radius"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            RadTanParams p{readIntrinsics(r, width, height), r.number("k1"), r.number("k2"),
                           r.number("p1"), r.number("p2"), r.number("k3", 0.0)};
            p.k4 = r.number("k4", 0.0);
            p.k5 = r.number("k5", 0.0);
            p.k6 = r.number("k6", 0.0);
            p.maxRadius = r.number("max_radius", 0.0);
            return construct<RadTanCamera>(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const RadTanParams& p = as<RadTanCamera>(camera).params();
            emitIntrinsics(out, p.intrinsics);
            emitNumbers(out, {{"k1", p.k1}, {"k2", p.k2}, {"p1", p.p1}, {"p2", p.p2}, {"k3", p.k3}});
            // The rational model's terms only when used, so a polynomial model's file stays as it was.
            if (p.k4 != 0.0 || p.k5 != 0.0 || p.k6 != 0.0) emitNumbers(out, {{"k4", p.k4}, {"k5", p.k5}, {"k6", p.k6}});
            if (p.maxRadius > 0.0) emitNumbers(out, {{"max_radius", p.maxRadius}});
          },
          {{"k1", "k2", "p1", "p2"}, {"k1", "k2", "k3", "p1", "p2"}}};
}

}  // namespace detail
}  // namespace mdbrief
