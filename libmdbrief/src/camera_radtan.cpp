#include "mdbrief/camera_radtan.hpp"

#include "camera_model_utils.hpp"

namespace mdbrief {
namespace {
// Beyond ~89 degrees from the axis a pinhole-based model is meaningless anyway.
constexpr double kRadiusSearchLimit = 50.0;
}  // namespace

RadTanCamera::RadTanCamera(const RadTanParams& params) : p_(params) {
  validateIntrinsics(p_.intrinsics, "radtan");
  detail::requireFinite("radtan", "k1", p_.k1);
  detail::requireFinite("radtan", "k2", p_.k2);
  detail::requireFinite("radtan", "p1", p_.p1);
  detail::requireFinite("radtan", "p2", p_.p2);
  detail::requireFinite("radtan", "k3", p_.k3);
  rMax_ = detail::firstNonIncreasing([this](double r) { return radialDistortedPrime(r); }, 0.0,
                                     kRadiusSearchLimit, 20000);
  rdMax_ = radialDistorted(rMax_);
}

double RadTanCamera::radialDistorted(double r) const {
  const double r2 = r * r;
  return r * (1.0 + r2 * (p_.k1 + r2 * (p_.k2 + r2 * p_.k3)));
}

double RadTanCamera::radialDistortedPrime(double r) const {
  const double r2 = r * r;
  return 1.0 + r2 * (3.0 * p_.k1 + r2 * (5.0 * p_.k2 + r2 * 7.0 * p_.k3));
}

cv::Vec2d RadTanCamera::distort(double x, double y) const {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (p_.k1 + r2 * (p_.k2 + r2 * p_.k3));
  return {x * radial + 2.0 * p_.p1 * x * y + p_.p2 * (r2 + 2.0 * x * x),
          y * radial + p_.p1 * (r2 + 2.0 * y * y) + 2.0 * p_.p2 * x * y};
}

bool RadTanCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const CameraIntrinsics& k = p_.intrinsics;
  const double xd = (pixel.x - k.cx) / k.fx, yd = (pixel.y - k.cy) / k.fy;
  const double rd = std::hypot(xd, yd);
  if (!std::isfinite(rd) || !(rd < rdMax_)) return false;
  if (rd == 0.0 && p_.p1 == 0.0 && p_.p2 == 0.0) {
    bearing = {0.0, 0.0, 1.0};
    return true;
  }
  // Start from the radial-only inverse (monotonic on [0, rMax]: bisection-safeguarded Newton).
  double lo = 0.0, hi = rMax_, r = std::min(rd, rMax_);
  for (int i = 0; i < 60; ++i) {
    const double f = radialDistorted(r) - rd;
    const double step = f / radialDistortedPrime(r);
    if (std::abs(step) < 1e-14) {
      r -= step;
      break;
    }
    (f > 0.0 ? hi : lo) = r;
    r -= step;
    if (!(r > lo && r < hi)) r = 0.5 * (lo + hi);
  }
  double x = rd > 0.0 ? xd * r / rd : 0.0, y = rd > 0.0 ? yd * r / rd : 0.0;
  // Newton on the full model with its 2x2 Jacobian to add the tangential part.
  for (int i = 0; i < 20; ++i) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (p_.k1 + r2 * (p_.k2 + r2 * p_.k3));
    // d(radial)/dx = x * dRadial, d(radial)/dy = y * dRadial.
    const double dRadial = 2.0 * (p_.k1 + r2 * (2.0 * p_.k2 + r2 * 3.0 * p_.k3));
    const cv::Vec2d e = distort(x, y) - cv::Vec2d(xd, yd);
    const double j00 = radial + x * x * dRadial + 2.0 * p_.p1 * y + 6.0 * p_.p2 * x;
    const double j01 = x * y * dRadial + 2.0 * p_.p1 * x + 2.0 * p_.p2 * y;
    const double j11 = radial + y * y * dRadial + 6.0 * p_.p1 * y + 2.0 * p_.p2 * x;
    const double det = j00 * j11 - j01 * j01;  // the Jacobian is symmetric
    if (!(std::abs(det) > 1e-300)) return false;
    const double dx = (j11 * e[0] - j01 * e[1]) / det, dy = (j00 * e[1] - j01 * e[0]) / det;
    x -= dx;
    y -= dy;
    if (std::abs(dx) + std::abs(dy) < 1e-14) break;
  }
  const cv::Vec2d residual = distort(x, y) - cv::Vec2d(xd, yd);
  if (!(cv::norm(residual) < 1e-9) || !(std::hypot(x, y) < rMax_)) return false;
  bearing = detail::normalized({x, y, 1.0});
  return true;
}

bool RadTanCamera::bearingToPixel(const cv::Vec3d& b, cv::Point2d& pixel) const {
  if (!(b[2] > 0.0)) return false;
  const double x = b[0] / b[2], y = b[1] / b[2];
  if (!(std::hypot(x, y) < rMax_)) return false;
  const cv::Vec2d d = distort(x, y);
  const CameraIntrinsics& k = p_.intrinsics;
  pixel = {k.fx * d[0] + k.cx, k.fy * d[1] + k.cy};
  return true;
}

bool RadTanCamera::isValid(const cv::Point2d& pixel) const {
  // Near the limit the tangential terms decide whether the inverse stays inside rMax, so the
  // test is the inversion itself (no closed form for the folded region).
  cv::Vec3d bearing;
  return detail::insideImage(pixel, p_.intrinsics.size()) && pixelToBearing(pixel, bearing);
}

std::shared_ptr<Camera> RadTanCamera::resized(cv::Size newSize) const {
  RadTanParams r = p_;
  r.intrinsics = resizeIntrinsics(p_.intrinsics, newSize);
  return std::make_shared<RadTanCamera>(r);
}

}  // namespace mdbrief
