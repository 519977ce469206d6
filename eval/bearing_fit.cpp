#include "bearing_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <opengv/relative_pose/CentralRelativeAdapter.hpp>
#include <opengv/relative_pose/methods.hpp>

namespace mdbrief::eval {

std::optional<EssentialFit> fitEssential(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                                         double pixelsPerRadian, const RansacOptions& o) {
  const int n = static_cast<int>(a.size());
  if (n < 5 || b.size() != a.size() || !(pixelsPerRadian > 0)) return std::nullopt;
  opengv::bearingVectors_t fa, fb;
  for (int k = 0; k < n; ++k) {
    fa.push_back(Eigen::Vector3d(a[k][0], a[k][1], a[k][2]).normalized());
    fb.push_back(Eigen::Vector3d(b[k][0], b[k][1], b[k][2]).normalized());
  }
  opengv::relative_pose::CentralRelativeAdapter adapter(fa, fb);
  const double limit = o.thresholdPx / pixelsPerRadian;
  const auto inliersOf = [&](const Eigen::Matrix3d& e, std::vector<char>& in) {
    in.assign(n, 0);
    int count = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d normal = e * fb[k];
      const double nn = normal.norm();
      in[k] = nn > 0 && std::abs(fa[k].dot(normal)) <= std::sin(limit) * nn;
      count += in[k];
    }
    return count;
  };
  // RANSAC over minimal samples of OpenGV's 5-point solver (Nister; up to 10 essential
  // matrices per sample, each scored), with this file's generator so that a run repeats.
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  Eigen::Matrix3d bestE;
  std::vector<char> bestIn, in;
  int bestCount = 0, needed = o.maxIterations;
  std::vector<int> sample(5);
  for (int it = 0; it < needed; ++it) {
    for (int s = 0; s < 5; ++s) {
      do sample[s] = pick(rng);
      while (std::find(sample.begin(), sample.begin() + s, sample[s]) != sample.begin() + s);
    }
    for (const auto& e : opengv::relative_pose::fivept_nister(adapter, sample)) {
      const int count = inliersOf(e, in);
      if (count > bestCount) {
        bestCount = count;
        bestE = e;
        bestIn = in;
        needed = ransacIterationsNeeded(static_cast<double>(count) / n, 5, o.confidence, o.maxIterations);
      }
    }
  }
  if (bestCount < 5) return std::nullopt;
  // E = [t]x R: of the four (R, t) it factors into, the one that puts most inliers in front of
  // both cameras; then OpenGV's non-linear refinement on the inliers.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(bestE, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
  if (u.determinant() < 0) u = -u;
  if (v.determinant() < 0) v = -v;
  Eigen::Matrix3d w;
  w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  std::vector<int> members;
  for (int k = 0; k < n; ++k)
    if (bestIn[k]) members.push_back(k);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  int bestFront = -1;
  for (const Eigen::Matrix3d& r : {Eigen::Matrix3d(u * w * v.transpose()), Eigen::Matrix3d(u * w.transpose() * v.transpose())})
    for (const Eigen::Vector3d& t : {Eigen::Vector3d(u.col(2)), Eigen::Vector3d(-u.col(2))}) {
      int front = 0;
      for (int k : members) {
        // depths: da fa = db R fb + t, least squares
        Eigen::Matrix<double, 3, 2> m;
        m.col(0) = fa[k];
        m.col(1) = -(r * fb[k]);
        const Eigen::Vector2d d = m.colPivHouseholderQr().solve(t);
        front += d[0] > 0 && d[1] > 0;
      }
      if (front > bestFront) bestFront = front, rotation = r, translation = t;
    }
  adapter.sett12(translation);
  adapter.setR12(rotation);
  const opengv::transformation_t refined = opengv::relative_pose::optimize_nonlinear(adapter, members);
  EssentialFit fit;
  Eigen::Vector3d t = refined.col(3);
  if (!(t.norm() > 0) || !t.allFinite()) return std::nullopt;
  t.normalize();
  const Eigen::Matrix3d r = refined.block<3, 3>(0, 0);
  Eigen::Matrix3d tx;
  tx << 0, -t[2], t[1], t[2], 0, -t[0], -t[1], t[0], 0;
  const int refinedCount = inliersOf(tx * r, in);
  // The refinement minimises another error than the inlier test; keep whichever explains more.
  const Eigen::Matrix3d e = refinedCount >= bestCount ? Eigen::Matrix3d(tx * r) : bestE;
  fit.inlierCount = inliersOf(e, fit.inliers);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) fit.essential(i, j) = e(i, j);
  return fit;
}

double epipolarAngle(const EssentialFit& fit, const cv::Vec3d& a, const cv::Vec3d& b) {
  const cv::Vec3d normal = fit.essential * b;
  const double nn = cv::norm(normal), an = cv::norm(a);
  if (!(nn > 0) || !(an > 0)) return std::numeric_limits<double>::infinity();
  return std::asin(std::min(1.0, std::abs(normal.dot(a)) / (nn * an)));
}

}  // namespace mdbrief::eval
