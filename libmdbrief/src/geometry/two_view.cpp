#include "mdbrief/geometry/two_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "geometry/two_view_support.hpp"

namespace mdbrief {

const OptionTable<TwoViewOptions>& twoViewOptionFields() {
  using O = TwoViewOptions;
  using R = FieldRange;
  static const OptionTable<O> table = {
      // Beyond half a radian (29 degrees) nothing is an outlier any more.
      realField<O>("maxAngle", "", "max_angle", "--max-angle", "inlier threshold, radians", R::openLow(0, 0.5),
                   [](auto& o) -> auto& { return o.maxAngle; }),
      realField<O>("maxPixels", "", "max_pixels", "--max-pixels",
                   "inlier threshold in pixels, when the pixels per radian of each match are given",
                   R::openLow(0, 1000), [](auto& o) -> auto& { return o.maxPixels; }),
      realField<O>("confidence", "", "confidence", "--confidence",
                   "RANSAC stops when a better model is this unlikely", R::open(0, 1),
                   [](auto& o) -> auto& { return o.confidence; }),
      integerField<O>("maxIterations", "", "max_iterations", "--max-iterations", "RANSAC samples at most",
                      R::closed(1, 1000000), [](auto& o) -> auto& { return o.maxIterations; }),
      integerField<O>("seed", "", "seed", "--seed", "RANSAC's random seed", R::closed(0, 4294967295.0),
                      [](auto& o) -> auto& { return o.seed; }),
      flagField<O>("refine", "", "refine", nullptr, "refine the model on its inliers",
                   [](auto& o) -> auto& { return o.refine; }),
      flagField<O>("inFront", "", "in_front", nullptr, "an inlier's point lies in front of both cameras",
                   [](auto& o) -> auto& { return o.inFront; }),
      realField<O>("maxFalseAlarms", "", "max_false_alarms", "--max-false-alarms",
                   "a model counts as found when random matches would give fewer as good",
                   R::openLow(0, 1e300), [](auto& o) -> auto& { return o.maxFalseAlarms; }),
  };
  return table;
}

void validate(const TwoViewOptions& options) { validateFields(twoViewOptionFields(), options, "TwoViewOptions"); }

const char* toString(TwoViewFailure failure) {
  switch (failure) {
    case TwoViewFailure::None:
      return "";
    case TwoViewFailure::TooFewMatches:
      return "too few matches";
    case TwoViewFailure::SamePoint:
      return "all matches on the same point";
    case TwoViewFailure::OnALine:
      return "all matches on a line";
    case TwoViewFailure::NoModel:
      return "no model found";
    case TwoViewFailure::NotSignificant:
      return "inliers no more than chance";
  }
  return "unknown failure";
}

cv::Matx33d essentialMatrix(const RelativePose& pose) {
  const cv::Vec3d& t = pose.translation;
  return cv::Matx33d(0, -t[2], t[1], t[2], 0, -t[0], -t[1], t[0], 0) * pose.rotation;
}

double epipolarAngle(const RelativePose& pose, const cv::Vec3d& a, const cv::Vec3d& b) {
  // Scaled by the largest component first, so that lengths of 1e200 or 1e-170 keep their direction.
  const auto unit = [](const cv::Vec3d& v, const char* name) {
    const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    if (!(largest > 0) || !std::isfinite(largest))
      throw std::invalid_argument(std::string("epipolarAngle: bearing ") + name + " must be finite and non-zero");
    const cv::Vec3d scaled = v / largest;
    return cv::Vec3d(scaled / cv::norm(scaled));
  };
  return geometry::epipolarResidual(essentialMatrix(pose), unit(a, "a"), unit(b, "b"));
}

std::optional<double> pixelsPerRadian(const Camera& camera, const cv::Point2d& pixel) {
  cv::Vec3d l, r, u, d;
  const double h = 0.5;
  if (!camera.pixelToBearing(pixel - cv::Point2d(h, 0), l) || !camera.pixelToBearing(pixel + cv::Point2d(h, 0), r) ||
      !camera.pixelToBearing(pixel - cv::Point2d(0, h), u) || !camera.pixelToBearing(pixel + cv::Point2d(0, h), d))
    return std::nullopt;
  using geometry::angleBetween;
  const double radiansPerPixel = 0.5 * (angleBetween(l, r) + angleBetween(u, d)) / (2 * h);
  if (!(radiansPerPixel > 0) || !std::isfinite(radiansPerPixel)) return std::nullopt;
  return 1.0 / radiansPerPixel;
}

int ransacIterationsNeeded(double w, int sampleSize, double confidence, int cap) {
  if (!(w >= 0 && w <= 1)) throw std::invalid_argument("ransacIterationsNeeded: w must be in [0, 1], got " + std::to_string(w));
  if (sampleSize < 1)
    throw std::invalid_argument("ransacIterationsNeeded: sampleSize must be at least 1, got " + std::to_string(sampleSize));
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument("ransacIterationsNeeded: confidence must be in (0, 1), got " + std::to_string(confidence));
  if (cap < 1) throw std::invalid_argument("ransacIterationsNeeded: cap must be at least 1, got " + std::to_string(cap));
  const double good = std::pow(w, sampleSize);
  if (good >= 1.0) return 1;
  if (good <= 0.0) return cap;
  const double k = std::log(1.0 - confidence) / std::log(1.0 - good);
  return k >= cap ? cap : std::max(1, static_cast<int>(std::ceil(k)));
}

TwoViewResult checkKnownPose(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                             const RelativePose& pose, const TwoViewOptions& options,
                             const std::vector<double>& pixelsPerRadian) {
  const geometry::CheckedMatches m = geometry::checkMatches("checkKnownPose", a, b, options, pixelsPerRadian);
  const cv::Matx33d& r = pose.rotation;
  const cv::Matx33d rtr = r.t() * r - cv::Matx33d::eye();
  if (!(cv::norm(rtr, cv::NORM_INF) <= 1e-6) || !(std::abs(cv::determinant(r) - 1.0) <= 1e-6))
    throw std::invalid_argument("checkKnownPose: pose.rotation is not a rotation (R^T R = I and det R = 1 within 1e-6)");
  const double tn = cv::norm(pose.translation);
  if (!(tn > 0) || !std::isfinite(tn))
    throw std::invalid_argument("checkKnownPose: pose.translation must be finite and non-zero (with no baseline, "
                                "matches have no epipolar geometry)");
  const cv::Vec3d t = pose.translation / tn;
  const cv::Matx33d e = essentialMatrix(RelativePose{r, t});
  const double parallel = m.typicalAngle();
  TwoViewResult result;
  result.inliers.assign(m.size(), 0);
  result.residuals.resize(m.size());
  for (int k = 0; k < m.size(); ++k) {
    result.residuals[k] = geometry::epipolarResidual(e, m.a[k], m.b[k]);
    result.inliers[k] = m.within(k, result.residuals[k]) &&
                        (!options.inFront || geometry::inFront(r, t, m.a[k], m.b[k], parallel));
    result.inlierCount += result.inliers[k];
  }
  return result;
}

namespace geometry {

double CheckedMatches::typicalAngle() const {
  if (scale.empty()) return maxAngle;
  double sum = 0;
  for (double s : scale) sum += maxPixels / s;
  return sum / static_cast<double>(scale.size());
}

CheckedMatches checkMatches(const char* function, const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                            const TwoViewOptions& options, const std::vector<double>& pixelsPerRadian) {
  const std::string name = function;
  try {
    validate(options);
  } catch (const OptionError& e) {
    throw OptionError(e.field(), name + ": " + twoViewOptionFields().at(e.field()).member, e.problem());
  }
  if (a.size() != b.size())
    throw std::invalid_argument(name + ": a has " + std::to_string(a.size()) + " bearings and b " +
                                std::to_string(b.size()) + "; one each per match");
  if (!pixelsPerRadian.empty() && pixelsPerRadian.size() != a.size())
    throw std::invalid_argument(name + ": pixelsPerRadian has " + std::to_string(pixelsPerRadian.size()) +
                                " values for " + std::to_string(a.size()) + " matches (one per match, or none)");
  CheckedMatches m;
  m.maxAngle = options.maxAngle;
  m.maxPixels = options.maxPixels;
  m.a.reserve(a.size());
  m.b.reserve(b.size());
  const auto unit = [&](const cv::Vec3d& v, const char* side, size_t k) {
    const double n = cv::norm(v);
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !(n > 0) || !std::isfinite(n))
      throw std::invalid_argument(name + ": bearing " + side + "[" + std::to_string(k) +
                                  "] must be finite and non-zero");
    return cv::Vec3d(v / n);
  };
  for (size_t k = 0; k < a.size(); ++k) {
    m.a.push_back(unit(a[k], "a", k));
    m.b.push_back(unit(b[k], "b", k));
  }
  for (size_t k = 0; k < pixelsPerRadian.size(); ++k)
    if (!(pixelsPerRadian[k] > 0) || !std::isfinite(pixelsPerRadian[k]))
      throw std::invalid_argument(name + ": pixelsPerRadian[" + std::to_string(k) + "] must be positive and finite, got " +
                                  std::to_string(pixelsPerRadian[k]));
  m.scale = pixelsPerRadian;
  return m;
}

namespace {

// Every bearing within `limit` of their mean direction.
bool onePoint(const std::vector<cv::Vec3d>& v, double limit) {
  cv::Vec3d sum(0, 0, 0);
  for (const auto& x : v) sum += x;
  if (!(cv::norm(sum) > 0)) return false;
  const cv::Vec3d mean = sum / cv::norm(sum);
  for (const auto& x : v)
    if (angleBetween(x, mean) > limit) return false;
  return true;
}

// Every bearing within `limit` of one plane through the centre: the plane whose normal is the
// direction of least spread (the scatter matrix's smallest eigenvector).
bool onePlane(const std::vector<cv::Vec3d>& v, double limit) {
  cv::Matx33d scatter = cv::Matx33d::zeros();
  for (const auto& x : v) scatter += x * x.t();
  cv::Mat values, vectors;
  cv::eigen(cv::Mat(scatter), values, vectors);  // descending
  const cv::Vec3d normal(vectors.at<double>(2, 0), vectors.at<double>(2, 1), vectors.at<double>(2, 2));
  const double bound = std::sin(limit);
  for (const auto& x : v)
    if (std::abs(x.dot(normal)) > bound) return false;
  return true;
}

}  // namespace

TwoViewFailure degeneracy(const CheckedMatches& m, int minimal) {
  if (m.size() < minimal) return TwoViewFailure::TooFewMatches;
  const double limit = m.typicalAngle();
  if (onePoint(m.a, limit) || onePoint(m.b, limit)) return TwoViewFailure::SamePoint;
  if (onePlane(m.a, limit) || onePlane(m.b, limit)) return TwoViewFailure::OnALine;
  return TwoViewFailure::None;
}

void fail(TwoViewResult& result, TwoViewFailure failure, int matches, int minimal) {
  result.failure = failure;
  result.reason = toString(failure);
  if (failure == TwoViewFailure::TooFewMatches || failure == TwoViewFailure::NoModel)
    result.reason += " (" + std::to_string(matches) + " matches, " + std::to_string(minimal) + " needed" +
                     (failure == TwoViewFailure::NoModel ? " as inliers)" : ")");
  else
    result.reason += " (of " + std::to_string(matches) + ")";
  result.inliers.assign(matches, 0);
  result.residuals.clear();
  result.inlierCount = 0;
}

double binomialTailLog10(int trials, int successes, double p) {
  if (successes <= 0 || p >= 1) return 0;
  if (successes > trials || !(p > 0)) return -std::numeric_limits<double>::infinity();
  // log-sum-exp of the terms from `successes` up; past the mode they fall geometrically, so the
  // sum stops once they no longer change it.
  const double lp = std::log(p), lq = std::log1p(-p), top = std::lgamma(trials + 1.0);
  const auto term = [&](int i) { return top - std::lgamma(i + 1.0) - std::lgamma(trials - i + 1.0) + i * lp + (trials - i) * lq; };
  double largest = term(successes), sum = 0;
  for (int i = successes; i <= trials; ++i) {
    const double t = term(i);
    if (t > largest) sum *= std::exp(largest - t), largest = t;
    sum += std::exp(t - largest);
    if (i > trials * p && t - largest < -46) break;  // below 1e-20 of the sum
  }
  return std::min(0.0, (largest + std::log(sum)) / std::log(10.0));
}

double significanceLog10(int models, int matches, int inliers, int sample, double chance) {
  return std::log10(std::max(models, 1)) + binomialTailLog10(matches - sample, inliers - sample, chance);
}

void failIfChance(TwoViewResult& result, double maxFalseAlarms, int matches, int sample) {
  if (result.log10FalseAlarms < std::log10(maxFalseAlarms)) return;
  const int inliers = result.inlierCount;
  const double nfa = result.log10FalseAlarms;
  fail(result, TwoViewFailure::NotSignificant, matches, sample);
  result.log10FalseAlarms = nfa;
  result.reason += ": " + std::to_string(inliers) + " inliers, 10^" + std::to_string(nfa).substr(0, 6) +
                   " false alarms, maxFalseAlarms " + std::to_string(maxFalseAlarms).substr(0, 8);
}

double angleBetween(const cv::Vec3d& u, const cv::Vec3d& v) { return std::atan2(cv::norm(u.cross(v)), u.dot(v)); }

double epipolarResidual(const cv::Matx33d& e, const cv::Vec3d& a, const cv::Vec3d& b) {
  const cv::Vec3d normal = e.t() * a;
  const double nn = cv::norm(normal);
  if (!(nn > 0)) return CV_PI / 2;
  return std::asin(std::min(1.0, std::abs(normal.dot(b)) / nn));
}

bool inFront(const cv::Matx33d& r, const cv::Vec3d& t, const cv::Vec3d& a, const cv::Vec3d& b, double parallel) {
  const cv::Vec3d rb = r * b;
  if (a.dot(rb) >= std::cos(parallel)) return true;  // unit vectors: within `parallel` radians
  // Depths of the least-squares point: da a = db R b + t.
  const double c = a.dot(rb), det = 1.0 - c * c;
  if (!(det > 0)) return false;
  const double at = a.dot(t), bt = rb.dot(t);
  const double da = (at - c * bt) / det, db = (c * at - bt) / det;
  return da > 0 && db > 0;
}

}  // namespace geometry
}  // namespace mdbrief
