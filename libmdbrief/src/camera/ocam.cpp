#include "mdbrief/camera/ocam.hpp"

// GCC 12 reports false -Wmaybe-uninitialized inside Eigen's AVX-512 kernels (-march=native);
// the warning is issued after inlining, so it can only be silenced for the whole file. Clang
// (the fuzzing build) has no such warning and would warn about the unknown name.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/Dense>

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {
namespace {

constexpr const char* kModel = "ocam";

void requireFiniteList(const std::vector<double>& values, const std::string& name) {
  for (std::size_t i = 0; i < values.size(); ++i)
    detail::requireFinite(kModel, name + "[" + std::to_string(i) + "]", values[i]);
}

// Least-squares polynomial rho(theta) through the samples, degree raised until the largest
// residual is below `tolerancePx` (or the best of degrees up to 20 when none reaches it).
std::vector<double> fitInversePolynomial(const std::vector<double>& theta,
                                         const std::vector<double>& rho, double tolerancePx) {
  std::vector<double> best;
  double bestError = std::numeric_limits<double>::infinity();
  const Eigen::Index n = static_cast<Eigen::Index>(theta.size());
  const Eigen::Map<const Eigen::VectorXd> target(rho.data(), n);
  for (int degree = 3; degree <= 20; ++degree) {
    Eigen::MatrixXd a(n, degree + 1);
    for (Eigen::Index i = 0; i < n; ++i) {
      double power = 1.0;
      for (int j = 0; j <= degree; ++j, power *= theta[i]) a(i, j) = power;
    }
    const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(target);
    const double error = (a * coef - target).cwiseAbs().maxCoeff();
    if (error < bestError) {
      bestError = error;
      best.assign(coef.data(), coef.data() + coef.size());
    }
    if (bestError < tolerancePx) break;
  }
  return best;
}

}  // namespace

OcamCamera::OcamCamera(const OcamParams& params) : p_(params) {
  detail::requirePositive(kModel, "width", p_.width);
  detail::requirePositive(kModel, "height", p_.height);
  if (p_.forward.size() < 2)
    detail::throwBadParameter(kModel, "forward", "needs at least 2 coefficients, count is",
                              static_cast<double>(p_.forward.size()));
  requireFiniteList(p_.forward, "forward");
  if (!(p_.forward[0] < 0.0))
    detail::throwBadParameter(kModel, "forward[0]",
                              "must be < 0 (OCamCalib convention: a z-forward polynomial must "
                              "have all coefficients negated)",
                              p_.forward[0]);
  if (p_.inverse.size() == 1)
    detail::throwBadParameter(kModel, "inverse", "needs at least 2 coefficients or none, count is",
                              1.0);
  requireFiniteList(p_.inverse, "inverse");
  detail::requireFinite(kModel, "c", p_.c);
  detail::requireFinite(kModel, "d", p_.d);
  detail::requireFinite(kModel, "e", p_.e);
  detail::requireFinite(kModel, "u0", p_.u0);
  detail::requireFinite(kModel, "v0", p_.v0);
  if (!std::isfinite(p_.validRadius) || p_.validRadius < 0.0)
    detail::throwBadParameter(kModel, "valid_radius", "must be finite and >= 0", p_.validRadius);
  const double det = p_.c - p_.d * p_.e;
  if (!(std::abs(det) > 1e-12))
    detail::throwBadParameter(kModel, "c", "gives a singular affine matrix (c - d e)", det);
  invDet_ = 1.0 / det;

  // Search the monotonic range up to beyond the farthest image corner (in the affine frame).
  double farthest = 0.0;
  for (const cv::Point2d corner : {cv::Point2d(0, 0), cv::Point2d(p_.width - 1.0, 0),
                                   cv::Point2d(0, p_.height - 1.0),
                                   cv::Point2d(p_.width - 1.0, p_.height - 1.0)}) {
    const double dr = corner.y - p_.v0, dc = corner.x - p_.u0;
    farthest = std::max(farthest, std::hypot(invDet_ * (dr - p_.d * dc),
                                              invDet_ * (-p_.e * dr + p_.c * dc)));
  }
  const auto& f = p_.forward;
  rhoMax_ = detail::firstNonIncreasing(
      [&f](double rho) { return detail::polyDerivEval(f, rho) * rho - detail::polyEval(f, rho); },
      0.0, 1.5 * farthest + 1.0);
  thetaMax_ = elevation(rhoMax_);

  if (p_.inverse.empty()) {
    constexpr int kSamples = 500;
    std::vector<double> theta(kSamples + 1), rho(kSamples + 1);
    for (int i = 0; i <= kSamples; ++i) {
      rho[i] = rhoMax_ * i / kSamples;
      theta[i] = elevation(rho[i]);
    }
    p_.inverse = fitInversePolynomial(theta, rho, 0.05);
  }
}

double OcamCamera::elevation(double rho) const {
  return std::atan2(detail::polyEval(p_.forward, rho), rho);
}

double OcamCamera::solveRho(double norm, double zo, double rho) const {
  // Root of F(rho) = norm f(rho) - zo rho, unique on [0, rhoMax] because f(rho)/rho increases
  // there; Newton from the inverse polynomial's guess, kept inside a shrinking bracket.
  double lo = 0.0, hi = rhoMax_;
  if (!(rho > lo && rho < hi)) rho = 0.5 * (lo + hi);
  for (int i = 0; i < 100; ++i) {
    const double value = norm * detail::polyEval(p_.forward, rho) - zo * rho;
    const double step = value / (norm * detail::polyDerivEval(p_.forward, rho) - zo);
    if (std::abs(step) < 1e-10) return rho - step;
    (value > 0.0 ? hi : lo) = rho;
    rho -= step;
    if (!(rho > lo && rho < hi)) rho = 0.5 * (lo + hi);
  }
  return rho;
}

bool OcamCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  const double dr = pixel.y - p_.v0, dc = pixel.x - p_.u0;
  const double xo = invDet_ * (dr - p_.d * dc);
  const double yo = invDet_ * (-p_.e * dr + p_.c * dc);
  const double rho = std::hypot(xo, yo);
  if (!(rho < rhoMax_)) return false;
  bearing = detail::normalized({yo, xo, -detail::polyEval(p_.forward, rho)});
  return true;
}

bool OcamCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  const double xo = b[1], yo = b[0], zo = -b[2];
  const double norm = std::hypot(xo, yo);
  if (!std::isfinite(norm) || !std::isfinite(zo)) return false;
  if (norm == 0.0) {
    if (!(zo < 0.0)) return false;
    pixel = {p_.u0, p_.v0};
    return true;
  }
  const double theta = std::atan2(zo, norm);
  if (!(theta < thetaMax_)) return false;
  const double rho = solveRho(norm, zo, detail::polyEval(p_.inverse, theta));
  const double x = xo / norm * rho, y = yo / norm * rho;
  pixel = {p_.e * x + y + p_.u0, p_.c * x + p_.d * y + p_.v0};
  return true;
}

bool OcamCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  const double xo = b[1], yo = b[0], zo = -b[2];
  const double norm = std::hypot(xo, yo);
  // d (x, y) / d (x_o, y_o, z_o), (x, y) = (x_o, y_o) rho / norm in the affine frame.
  cv::Matx23d frame;
  if (norm == 0.0) {  // on the axis rho = a0 norm / z_o to first order
    const double g = p_.forward.front() / zo;
    frame = {g, 0.0, 0.0, 0.0, g, 0.0};
  } else {
    // rho solves F = norm f(rho) - z_o rho = 0 (solveRho): implicit derivatives.
    const double dr = pixel.y - p_.v0, dc = pixel.x - p_.u0;
    const double rho = std::hypot(invDet_ * (dr - p_.d * dc), invDet_ * (-p_.e * dr + p_.c * dc));
    const double fRho = norm * detail::polyDerivEval(p_.forward, rho) - zo;
    const double dRhoDNorm = -detail::polyEval(p_.forward, rho) / fRho, dRhoDZo = rho / fRho;
    const cv::Vec3d dNorm(xo / norm, yo / norm, 0.0);
    const cv::Vec3d dRho = dRhoDNorm * dNorm + cv::Vec3d(0.0, 0.0, dRhoDZo);
    const double q = rho / norm;
    const cv::Vec3d dQ = (dRho - q * dNorm) / norm;  // d (rho / norm)
    frame = {q + xo * dQ[0], xo * dQ[1], xo * dQ[2], yo * dQ[0], q + yo * dQ[1], yo * dQ[2]};
  }
  const cv::Matx23d image = cv::Matx22d(p_.e, 1.0, p_.c, p_.d) * frame;
  // Bearing (X, Y, Z) = (y_o, x_o, -z_o).
  jacobian = {image(0, 1), image(0, 0), -image(0, 2), image(1, 1), image(1, 0), -image(1, 2)};
  return true;
}

bool OcamCamera::isValid(const cv::Point2d& pixel) const {
  if (!detail::insideImage(pixel, imageSize())) return false;
  const double dr = pixel.y - p_.v0, dc = pixel.x - p_.u0;
  if (p_.validRadius > 0.0 && detail::hypotAbove(dr, dc, p_.validRadius)) return false;
  return detail::hypotBelow(invDet_ * (dr - p_.d * dc), invDet_ * (-p_.e * dr + p_.c * dc), rhoMax_);
}

std::shared_ptr<Camera> OcamCamera::resized(cv::Size newSize) const {
  const cv::Vec2d s = detail::resizeScale(imageSize(), newSize, kModel);
  const double sx = s[0], sy = s[1];
  OcamParams r = p_;
  r.width = newSize.width;
  r.height = newSize.height;
  r.u0 = detail::resizeCoordinate(p_.u0, sx);
  r.v0 = detail::resizeCoordinate(p_.v0, sy);
  // Rows scale by sy, columns by sx: factor sx out so the matrix keeps the form [c' d'; e 1].
  r.c = p_.c * sy / sx;
  r.d = p_.d * sy / sx;
  // rho' = sx rho and the ray scales by sx too: a_i' = a_i sx^(1-i), b_i' = b_i sx.
  double power = sx;
  for (double& a : r.forward) {
    a *= power;
    power /= sx;
  }
  for (double& b : r.inverse) b *= sx;
  r.validRadius = p_.validRadius * std::sqrt(sx * sy);
  return std::make_shared<OcamCamera>(r);
}

// The model in the calibration files (camera/registry.hpp).
namespace detail {
namespace {

void emitList(YAML::Emitter& out, const char* key, const std::vector<double>& values) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const double v : values) out << v;
  out << YAML::EndSeq;
}

}  // namespace

ModelFormat ocamModelFormat() {
  return {"ocam", {"forward", "inverse", "c", "d", "e", "u0", "v0", "valid_radius"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            OcamParams p;
            p.width = width;
            p.height = height;
            p.forward = r.numbers("forward");
            if (r.has("inverse")) p.inverse = r.numbers("inverse");
            p.c = r.number("c");
            p.d = r.number("d");
            p.e = r.number("e");
            p.u0 = r.number("u0");
            p.v0 = r.number("v0");
            p.validRadius = r.number("valid_radius", 0.0);
            return makeOcam(source, p);
          },
          [](const Camera& camera, YAML::Emitter& out) {
            const OcamParams& p = as<OcamCamera>(camera).params();
            emitList(out, "forward", p.forward);
            emitList(out, "inverse", p.inverse);
            emitNumbers(out, {{"c", p.c}, {"d", p.d}, {"e", p.e}, {"u0", p.u0}, {"v0", p.v0}});
            if (p.validRadius > 0.0) emitNumbers(out, {{"valid_radius", p.validRadius}});
          },
          {}};  // the adapter writes OCam in a layout of its own (loadCalibAdapterYaml)
}

}  // namespace detail
}  // namespace mdbrief
