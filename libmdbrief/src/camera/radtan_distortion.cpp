#include "camera/radtan_distortion.hpp"

#include <cmath>
#include <limits>

#include "camera/model_utils.hpp"

namespace mdbrief::detail {

RadTanDistortion::RadTanDistortion(const RadTanCoefficients& c, const char* model, double searchLimit, double limit)
    : c_(c) {
  const std::pair<const char*, double> named[] = {{"k1", c.k1}, {"k2", c.k2}, {"p1", c.p1}, {"p2", c.p2},
                                                  {"k3", c.k3}, {"k4", c.k4}, {"k5", c.k5}, {"k6", c.k6}};
  for (const auto& [name, value] : named) requireFinite(model, name, value);
  rMax_ = firstNonIncreasing([this](double r) { return radialDistortedPrime(r); }, 0.0, searchLimit, 20000);
  if (limit > 0.0) rMax_ = std::min(rMax_, limit);
  rdMax_ = radialDistorted(rMax_);
}

double RadTanDistortion::radial(double r2) const {
  return (1.0 + r2 * (c_.k1 + r2 * (c_.k2 + r2 * c_.k3))) / (1.0 + r2 * (c_.k4 + r2 * (c_.k5 + r2 * c_.k6)));
}

double RadTanDistortion::radialDistorted(double r) const { return r * radial(r * r); }

double RadTanDistortion::radialDistortedPrime(double r) const {
  const double r2 = r * r;
  const double den = 1.0 + r2 * (c_.k4 + r2 * (c_.k5 + r2 * c_.k6));
  if (!(den > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // (P' den - P den') / den^2 with P = r * numerator: P' alone when the denominator is 1.
  const double numeratorPrime = 1.0 + r2 * (3.0 * c_.k1 + r2 * (5.0 * c_.k2 + r2 * 7.0 * c_.k3));
  const double numerator = r * (1.0 + r2 * (c_.k1 + r2 * (c_.k2 + r2 * c_.k3)));
  const double denPrime = r * (2.0 * c_.k4 + r2 * (4.0 * c_.k5 + r2 * 6.0 * c_.k6));
  return (numeratorPrime * den - numerator * denPrime) / (den * den);
}

cv::Vec2d RadTanDistortion::distort(double x, double y) const {
  const double r2 = x * x + y * y;
  const double factor = radial(r2);
  return {x * factor + 2.0 * c_.p1 * x * y + c_.p2 * (r2 + 2.0 * x * x),
          y * factor + c_.p1 * (r2 + 2.0 * y * y) + 2.0 * c_.p2 * x * y};
}

cv::Matx22d RadTanDistortion::jacobian(double x, double y) const {
  const double r2 = x * x + y * y;
  const double num = 1.0 + r2 * (c_.k1 + r2 * (c_.k2 + r2 * c_.k3));
  const double den = 1.0 + r2 * (c_.k4 + r2 * (c_.k5 + r2 * c_.k6));
  const double factor = num / den;
  // d(factor)/dx = x * dRadial, d(factor)/dy = y * dRadial (quotient rule on r^2).
  const double numPrime = c_.k1 + r2 * (2.0 * c_.k2 + r2 * 3.0 * c_.k3);
  const double denPrime = c_.k4 + r2 * (2.0 * c_.k5 + r2 * 3.0 * c_.k6);
  const double dRadial = 2.0 * ((numPrime * den - num * denPrime) / (den * den));
  const double j00 = factor + x * x * dRadial + 2.0 * c_.p1 * y + 6.0 * c_.p2 * x;
  const double j01 = x * y * dRadial + 2.0 * c_.p1 * x + 2.0 * c_.p2 * y;
  const double j11 = factor + y * y * dRadial + 6.0 * c_.p1 * y + 2.0 * c_.p2 * x;
  return {j00, j01, j01, j11};
}

bool RadTanDistortion::undistort(double xd, double yd, cv::Vec2d& undistorted) const {
  const double rd = std::hypot(xd, yd);
  if (!std::isfinite(rd) || !(rd < rdMax_)) return false;
  if (rd == 0.0 && c_.p1 == 0.0 && c_.p2 == 0.0) {
    undistorted = {0.0, 0.0};
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
    const cv::Matx22d j = jacobian(x, y);
    const double j00 = j(0, 0), j01 = j(0, 1), j11 = j(1, 1);
    const cv::Vec2d e = distort(x, y) - cv::Vec2d(xd, yd);
    const double det = j00 * j11 - j01 * j01;  // the Jacobian is symmetric
    if (!(std::abs(det) > 1e-300)) return false;
    const double dx = (j11 * e[0] - j01 * e[1]) / det, dy = (j00 * e[1] - j01 * e[0]) / det;
    x -= dx;
    y -= dy;
    if (std::abs(dx) + std::abs(dy) < 1e-14) break;
  }
  const cv::Vec2d residual = distort(x, y) - cv::Vec2d(xd, yd);
  if (!(cv::norm(residual) < 1e-9) || !(std::hypot(x, y) < rMax_)) return false;
  undistorted = {x, y};
  return true;
}

}  // namespace mdbrief::detail
