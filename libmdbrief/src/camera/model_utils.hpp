#pragma once
// Small helpers shared by the camera model implementations (private to the library).
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief::detail {

// Throws std::invalid_argument "<model>: <name> <what> (got <value>)".
[[noreturn]] inline void throwBadParameter(const std::string& model, const std::string& name,
                                           const std::string& what, double value) {
  std::ostringstream msg;
  msg.precision(17);
  msg << model << ": parameter '" << name << "' " << what << " (got " << value << ")";
  throw std::invalid_argument(msg.str());
}

inline void requireFinite(const std::string& model, const std::string& name, double value) {
  if (!std::isfinite(value)) throwBadParameter(model, name, "must be finite", value);
}

inline void requirePositive(const std::string& model, const std::string& name, double value) {
  if (!std::isfinite(value) || value <= 0.0)
    throwBadParameter(model, name, "must be finite and > 0", value);
}

// Inside [0, w-1] x [0, h-1]; false for NaN coordinates.
inline bool insideImage(const cv::Point2d& p, const cv::Size& size) {
  return p.x >= 0.0 && p.y >= 0.0 && p.x <= size.width - 1.0 && p.y <= size.height - 1.0;
}

// hypot(x, y) < limit and hypot(x, y) > limit, exactly as std::hypot decides them (NaN: false),
// for the valid-area checks the descriptor makes at every test footprint's corners. glibc's
// hypot is slow; the square sum is within a few ulps of hypot's square, so it decides every
// case outside a relative band of 1e-9 around the limit, and hypot decides the band.
inline bool hypotBelow(double x, double y, double limit) {
  const double s = x * x + y * y, l2 = limit * limit;
  if (s < l2 * (1.0 - 1e-9)) return true;
  if (s > l2 * (1.0 + 1e-9)) return false;
  return std::hypot(x, y) < limit;
}
inline bool hypotAbove(double x, double y, double limit) {
  const double s = x * x + y * y, l2 = limit * limit;
  if (s > l2 * (1.0 + 1e-9)) return true;
  if (s < l2 * (1.0 - 1e-9)) return false;
  return std::hypot(x, y) > limit;
}

// Horner evaluation of sum_i c[i] x^i.
inline double polyEval(const std::vector<double>& c, double x) {
  double y = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) y = y * x + *it;
  return y;
}

// Derivative of sum_i c[i] x^i.
inline double polyDerivEval(const std::vector<double>& c, double x) {
  double y = 0.0;
  for (std::size_t i = c.size(); i-- > 1;) y = y * x + static_cast<double>(i) * c[i];
  return y;
}

// First x in (lo, hi] where derivative(x) <= 0, located to ~1e-12 relative by bisection after a
// scan of `samples` steps; returns hi when the derivative stays positive. Used to cut every
// model at the end of its monotonic (invertible) range.
template <class Derivative>
double firstNonIncreasing(const Derivative& derivative, double lo, double hi, int samples = 4000) {
  double prev = lo;
  for (int i = 1; i <= samples; ++i) {
    const double x = lo + (hi - lo) * i / samples;
    if (!(derivative(x) > 0.0)) {
      double a = prev, b = x;  // derivative(a) > 0, derivative(b) <= 0
      for (int k = 0; k < 100 && b - a > 1e-12 * std::max(1.0, std::abs(b)); ++k) {
        const double m = 0.5 * (a + b);
        (derivative(m) > 0.0 ? a : b) = m;
      }
      return a;
    }
    prev = x;
  }
  return hi;
}

// Scale factors of a cv::resize-style resample; throws for a non-positive size.
inline cv::Vec2d resizeScale(const cv::Size& from, const cv::Size& to, const std::string& model) {
  if (to.width <= 0 || to.height <= 0)
    throw std::invalid_argument(model + ": resized() needs a positive size, got " + internal::sizeText(to));
  return {static_cast<double>(to.width) / from.width, static_cast<double>(to.height) / from.height};
}

// Pixel-centre coordinate after a resample by `scale` (cv::resize geometry).
inline double resizeCoordinate(double x, double scale) { return (x + 0.5) * scale - 0.5; }

inline cv::Vec3d normalized(const cv::Vec3d& v) { return v / cv::norm(v); }

// d (x / z, y / z) / d (x, y, z): the perspective division the pinhole-based models start with.
inline cv::Matx23d perspectiveJacobian(const cv::Vec3d& b) {
  const double iz = 1.0 / b[2];
  return {iz, 0.0, -b[0] * iz * iz, 0.0, iz, -b[1] * iz * iz};
}

// Rows scaled by the focal lengths: d pixel / d (normalised coordinates) times `m`.
template <int N>
cv::Matx<double, 2, N> scaleRows(double fx, double fy, const cv::Matx<double, 2, N>& m) {
  cv::Matx<double, 2, N> out = m;
  for (int c = 0; c < N; ++c) out(0, c) *= fx, out(1, c) *= fy;
  return out;
}

// d pixel / d bearing of the models whose pixel is f * (x, y) / denom + c with denom a function
// of the bearing (double sphere, UCM / EUCM), from d denom / d bearing.
inline cv::Matx23d rationalJacobian(double fx, double fy, const cv::Vec3d& b, double denom, const cv::Vec3d& dDenom) {
  const double i = 1.0 / denom;
  return {fx * i * (1.0 - b[0] * i * dDenom[0]), -fx * i * b[0] * i * dDenom[1], -fx * i * b[0] * i * dDenom[2],
          -fy * i * b[1] * i * dDenom[0], fy * i * (1.0 - b[1] * i * dDenom[1]), -fy * i * b[1] * i * dDenom[2]};
}

}  // namespace mdbrief::detail
