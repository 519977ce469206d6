// fitHomography: b ~ H a with a positive factor (a plane seen from one side, or a pure
// rotation): 4-point DLT in RANSAC, refitted on its inliers, then refined by Levenberg-Marquardt
// on the inliers' residuals in b's tangent plane.

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "geometry/two_view_support.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief {
namespace {

using geometry::angleBetween;
using geometry::CheckedMatches;
constexpr int kSample = 4;

// Least-squares DLT of b ~ H a over `indices`: each pair gives b x (H a) = 0, three equations
// of rank two. Bearings are unit vectors, so no normalisation is needed. Empty when degenerate.
std::optional<cv::Matx33d> solveHomography(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                                           const std::vector<int>& indices) {
  cv::Mat m(static_cast<int>(indices.size()) * 3, 9, CV_64F, cv::Scalar(0));
  for (size_t k = 0; k < indices.size(); ++k) {
    const cv::Vec3d& p = a[indices[k]];
    const cv::Vec3d& q = b[indices[k]];
    double* r0 = m.ptr<double>(static_cast<int>(3 * k));
    double* r1 = m.ptr<double>(static_cast<int>(3 * k + 1));
    double* r2 = m.ptr<double>(static_cast<int>(3 * k + 2));
    for (int c = 0; c < 3; ++c) {
      // row 0: q_y (h3 . p) - q_z (h2 . p)
      r0[3 + c] = -q[2] * p[c];
      r0[6 + c] = q[1] * p[c];
      // row 1: q_z (h1 . p) - q_x (h3 . p)
      r1[c] = q[2] * p[c];
      r1[6 + c] = -q[0] * p[c];
      // row 2: q_x (h2 . p) - q_y (h1 . p)
      r2[c] = -q[1] * p[c];
      r2[3 + c] = q[0] * p[c];
    }
  }
  // The null vector of m from the 9x9 normal matrix: an order of magnitude faster than an SVD
  // of m, and accurate enough in doubles for unit bearings.
  cv::Mat normal, values, vectors;
  cv::mulTransposed(m, normal, true);
  cv::eigen(normal, values, vectors);  // eigenvalues descending
  // A minimal sample with three collinear points leaves a null space of dimension > 1.
  if (indices.size() == 4 && !(values.at<double>(7) > 1e-18 * values.at<double>(0))) return std::nullopt;
  cv::Matx33d h;
  for (int i = 0; i < 9; ++i) h.val[i] = vectors.at<double>(8, i);
  const double det = cv::determinant(h);
  if (!(std::abs(det) > 1e-12) || !std::isfinite(det)) return std::nullopt;
  return h;
}

// Orients h so that h a . b > 0 on the sample; empty when the sample disagrees (no plane seen
// from one side explains it).
std::optional<cv::Matx33d> orient(cv::Matx33d h, const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                                  const std::vector<int>& indices) {
  int positive = 0;
  for (int i : indices) positive += (h * a[i]).dot(b[i]) > 0;
  if (positive == 0) return cv::Matx33d(-h);
  if (positive == static_cast<int>(indices.size())) return h;
  return std::nullopt;
}

// The angle between b and h a; a prediction pointing away from b is never an inlier.
double residual(const cv::Matx33d& h, const cv::Vec3d& a, const cv::Vec3d& b, bool& facing) {
  const cv::Vec3d v = h * a;
  facing = v.dot(b) > 0;
  return angleBetween(v, b);
}

int countInliers(const cv::Matx33d& h, const CheckedMatches& m, std::vector<unsigned char>& inliers) {
  inliers.assign(m.size(), 0);
  int n = 0;
  for (int k = 0; k < m.size(); ++k) {
    bool facing = false;
    const double r = residual(h, m.a[k], m.b[k], facing);
    inliers[k] = facing && m.within(k, r);
    n += inliers[k];
  }
  return n;
}

// Residual of b against h a in b's tangent plane (two components, angles times the local pixel
// scale, or angles).
void tangentResidual(const cv::Matx33d& h, const cv::Vec3d& a, const cv::Vec3d& b, double scale, double* out) {
  cv::Vec3d v = h * a;
  v /= cv::norm(v);
  // An orthonormal basis of b's tangent plane.
  const cv::Vec3d helper = std::abs(b[0]) < 0.9 ? cv::Vec3d(1, 0, 0) : cv::Vec3d(0, 1, 0);
  const cv::Vec3d e1 = cv::normalize(b.cross(helper)), e2 = b.cross(e1);
  out[0] = v.dot(e1) * scale;
  out[1] = v.dot(e2) * scale;
}

// Levenberg-Marquardt on the tangent residuals of the inliers (the DLT minimises an algebraic
// error, which weighs rays by where they are): what a user's pipeline does after RANSAC.
cv::Matx33d refineHomography(cv::Matx33d h, const CheckedMatches& m, const std::vector<int>& members) {
  const int rows = static_cast<int>(members.size()) * 2;
  const auto residuals = [&](const cv::Matx33d& g, cv::Mat& r) {
    r.create(rows, 1, CV_64F);
    for (size_t k = 0; k < members.size(); ++k) {
      const int i = members[k];
      tangentResidual(g, m.a[i], m.b[i], m.scale.empty() ? 1.0 : m.scale[i], r.ptr<double>(static_cast<int>(2 * k)));
    }
    return r.dot(r);
  };
  h *= 1.0 / cv::norm(h);
  cv::Mat r, trial, jac(rows, 9, CV_64F);
  double cost = residuals(h, r), lambda = 1e-3;
  for (int iteration = 0; iteration < 20; ++iteration) {
    for (int p = 0; p < 9; ++p) {  // forward differences: h has unit norm, so steps are relative
      cv::Matx33d g = h;
      g.val[p] += 1e-7;
      residuals(g, trial);
      jac.col(p) = (trial - r) / 1e-7;
    }
    const cv::Mat jtj = jac.t() * jac, jtr = jac.t() * r;
    bool improved = false;
    while (lambda < 1e8) {
      cv::Mat damped = jtj.clone(), step;
      for (int p = 0; p < 9; ++p) damped.at<double>(p, p) *= 1.0 + lambda;
      if (!cv::solve(damped, -jtr, step, cv::DECOMP_CHOLESKY)) break;
      cv::Matx33d g = h;
      for (int p = 0; p < 9; ++p) g.val[p] += step.at<double>(p);
      g *= 1.0 / cv::norm(g);
      const double c = residuals(g, trial);
      if (c < cost) {
        improved = cost - c > 1e-10 * cost;
        h = g, cost = c, r = trial.clone(), lambda = std::max(lambda * 0.1, 1e-9);
        break;
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
  return h;
}

}  // namespace

HomographyResult fitHomography(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                               const TwoViewOptions& o, const std::vector<double>& pixelsPerRadian) {
  const CheckedMatches m = geometry::checkMatches("fitHomography", a, b, o, pixelsPerRadian);
  HomographyResult result;
  const int n = m.size();
  if (const TwoViewFailure f = geometry::degeneracy(m, kSample); f != TwoViewFailure::None) {
    geometry::fail(result, f, n, kSample);
    return result;
  }
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  cv::Matx33d best;
  std::vector<unsigned char> bestInliers, inliers;
  int bestCount = 0, needed = o.maxIterations, models = 0;
  std::vector<int> sample(kSample);
  for (int it = 0; it < needed; ++it) {
    if (o.interruptCheck) o.interruptCheck();
    for (int s = 0; s < kSample; ++s) {
      do sample[s] = pick(rng);
      while (std::find(sample.begin(), sample.begin() + s, sample[s]) != sample.begin() + s);
    }
    auto h = solveHomography(m.a, m.b, sample);
    if (h) h = orient(*h, m.a, m.b, sample);
    if (!h) continue;
    ++models;
    const int count = countInliers(*h, m, inliers);
    if (count > bestCount) {
      best = *h;
      bestCount = count;
      bestInliers = inliers;
      needed = ransacIterationsNeeded(static_cast<double>(count) / n, kSample, o.confidence, o.maxIterations);
    }
  }
  if (bestCount < kSample) {
    geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
    return result;
  }
  const int sampledCount = bestCount;  // what the significance test counts (maxFalseAlarms)
  const auto membersOf = [&](const std::vector<unsigned char>& in) {
    std::vector<int> members;
    for (int k = 0; k < n; ++k)
      if (in[k]) members.push_back(k);
    return members;
  };
  // Refit on the inliers while that keeps or adds inliers (a local optimisation step).
  for (int round = 0; round < 5; ++round) {
    const std::vector<int> members = membersOf(bestInliers);
    auto h = solveHomography(m.a, m.b, members);
    if (!h) break;
    // The least-squares fit keeps the sign convention of the majority.
    int positive = 0;
    for (int k : members) positive += ((*h) * m.a[k]).dot(m.b[k]) > 0;
    if (2 * positive < static_cast<int>(members.size())) *h = -*h;
    const int count = countInliers(*h, m, inliers);
    if (count < bestCount) break;
    const bool grew = count > bestCount;
    best = *h;
    bestCount = count;
    bestInliers = inliers;
    if (!grew) break;
  }
  // The refined model is kept even when a borderline inlier moves past the threshold: it fits
  // the inliers better than the DLT's algebraic error, and it is what a pipeline keeps
  // (cv::findHomography refines its inliers the same way). Keeping the DLT whenever one of
  // hundreds of inliers moved left fits of 0.3 px where the refined one was within 0.05 px.
  if (o.refine) best = refineHomography(best, m, membersOf(bestInliers));
  best *= 1.0 / cv::norm(best);
  result.inlierCount = countInliers(best, m, result.inliers);
  if (result.inlierCount < kSample) {
    geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
    return result;
  }
  result.homography = best;
  result.residuals.resize(n);
  for (int k = 0; k < n; ++k) {
    bool facing = false;
    result.residuals[k] = residual(best, m.a[k], m.b[k], facing);
  }
  // Would random matches give as many inliers? A bearing lies within angle x of a direction
  // with probability (1 - cos x) / 2 when bearings spread over the sphere.
  const double chance =
      geometry::chanceShare(n, o.seed, 0.5 * (1.0 - std::cos(m.typicalAngle())), [&](int ka, int kb) {
        bool facing = false;
        const double r = residual(best, m.a[ka], m.b[kb], facing);
        return facing && m.within(kb, r);
      });
  result.log10FalseAlarms =
      geometry::significanceLog10(models, n, std::min(result.inlierCount, sampledCount), kSample, chance);
  geometry::failIfChance(result, o.maxFalseAlarms, n, kSample);
  if (!result.ok()) result.homography = cv::Matx33d();
  return result;
}

}  // namespace mdbrief
