// fitEssential: RANSAC over OpenGV's 5-point solver (Nister), the pose factored out of the best
// essential matrix, OpenGV's non-linear refinement on the inliers.
#include <algorithm>
#include <cmath>
#include <random>

#include <opengv/relative_pose/CentralRelativeAdapter.hpp>
#include <opengv/relative_pose/methods.hpp>

#include "geometry/two_view_support.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief {
namespace {

constexpr int kSample = 5;

cv::Matx33d toCv(const Eigen::Matrix3d& m) {
  cv::Matx33d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = m(i, j);
  return out;
}

// Labels every match under the pose: residual, threshold, and (options) in front.
int label(const geometry::CheckedMatches& m, const RelativePose& pose, bool front, std::vector<double>& residuals,
          std::vector<unsigned char>& inliers) {
  const cv::Matx33d e = pose.essential();
  const double parallel = m.typicalAngle();
  residuals.resize(m.size());
  inliers.assign(m.size(), 0);
  int count = 0;
  for (int k = 0; k < m.size(); ++k) {
    residuals[k] = geometry::epipolarResidual(e, m.a[k], m.b[k]);
    inliers[k] = m.within(k, residuals[k]) &&
                 (!front || geometry::inFront(pose.rotation, pose.translation, m.a[k], m.b[k], parallel));
    count += inliers[k];
  }
  return count;
}

}  // namespace

EssentialResult fitEssential(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                             const TwoViewOptions& options, const std::vector<double>& pixelsPerRadian) {
  const geometry::CheckedMatches m = geometry::checkMatches("fitEssential", a, b, options, pixelsPerRadian);
  EssentialResult result;
  const int n = m.size();
  if (const TwoViewFailure f = geometry::degeneracy(m, kSample); f != TwoViewFailure::None) {
    geometry::fail(result, f, n, kSample);
    return result;
  }
  opengv::bearingVectors_t fa, fb;
  fa.reserve(n);
  fb.reserve(n);
  for (int k = 0; k < n; ++k) {
    fa.emplace_back(m.a[k][0], m.a[k][1], m.a[k][2]);
    fb.emplace_back(m.b[k][0], m.b[k][1], m.b[k][2]);
  }
  // The inlier test of RANSAC without a transcendental function per match and model:
  // |a . n| <= sin(limit) |n| for the epipolar plane's normal n = E b.
  std::vector<double> sinLimit(n);
  for (int k = 0; k < n; ++k) {
    const double limit = m.scale.empty() ? m.maxAngle : m.maxPixels / m.scale[k];
    sinLimit[k] = limit >= CV_PI / 2 ? 1.0 : std::sin(limit);
  }
  const auto countInliers = [&](const Eigen::Matrix3d& e) {
    int count = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d normal = e * fb[k];
      count += std::abs(fa[k].dot(normal)) <= sinLimit[k] * normal.norm();
    }
    return count;
  };

  opengv::relative_pose::CentralRelativeAdapter adapter(fa, fb);
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  Eigen::Matrix3d bestE;
  int bestCount = 0, needed = options.maxIterations;
  std::vector<int> sample(kSample);
  for (int it = 0; it < needed; ++it) {
    for (int s = 0; s < kSample; ++s) {
      do sample[s] = pick(rng);
      while (std::find(sample.begin(), sample.begin() + s, sample[s]) != sample.begin() + s);
    }
    // Up to 10 essential matrices per sample, each scored.
    for (const auto& e : opengv::relative_pose::fivept_nister(adapter, sample)) {
      if (!e.allFinite()) continue;
      const int count = countInliers(e);
      if (count > bestCount) {
        bestCount = count;
        bestE = e;
        needed = ransacIterationsNeeded(static_cast<double>(count) / n, kSample, options.confidence,
                                        options.maxIterations);
      }
    }
  }
  if (bestCount < kSample) {
    geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
    return result;
  }

  // E = [t]x R factors into four poses; the one that puts most inliers in front of both cameras.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(bestE, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
  if (u.determinant() < 0) u = -u;
  if (v.determinant() < 0) v = -v;
  Eigen::Matrix3d w;
  w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  std::vector<double> residuals;
  std::vector<unsigned char> inliers;
  RelativePose pose;
  int poseCount = -1;
  for (const Eigen::Matrix3d& r :
       {Eigen::Matrix3d(u * w * v.transpose()), Eigen::Matrix3d(u * w.transpose() * v.transpose())})
    for (const Eigen::Vector3d& t : {Eigen::Vector3d(u.col(2)), Eigen::Vector3d(-u.col(2))}) {
      const RelativePose candidate{toCv(r), cv::Vec3d(t[0], t[1], t[2])};
      const int count = label(m, candidate, true, residuals, inliers);
      if (count > poseCount) poseCount = count, pose = candidate;
    }
  int count = label(m, pose, options.inFront, residuals, inliers);

  if (options.refine && count >= kSample) {
    std::vector<int> members;
    for (int k = 0; k < n; ++k)
      if (inliers[k]) members.push_back(k);
    Eigen::Matrix3d r0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r0(i, j) = pose.rotation(i, j);
    adapter.setR12(r0);
    adapter.sett12(Eigen::Vector3d(pose.translation[0], pose.translation[1], pose.translation[2]));
    const opengv::transformation_t refined = opengv::relative_pose::optimize_nonlinear(adapter, members);
    const Eigen::Vector3d t = refined.col(3);
    if (refined.allFinite() && t.norm() > 0) {
      const Eigen::Vector3d tu = t.normalized();
      const RelativePose candidate{toCv(refined.block<3, 3>(0, 0)), cv::Vec3d(tu[0], tu[1], tu[2])};
      std::vector<double> refinedResiduals;
      std::vector<unsigned char> refinedInliers;
      const int refinedCount = label(m, candidate, options.inFront, refinedResiduals, refinedInliers);
      // The refinement minimises another error than the inlier test; keep it unless it explains
      // fewer matches.
      if (refinedCount >= count) {
        pose = candidate, count = refinedCount;
        residuals.swap(refinedResiduals);
        inliers.swap(refinedInliers);
      }
    }
  }
  if (count < kSample) {
    geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
    return result;
  }
  result.pose = pose;
  result.essential = pose.essential();
  result.residuals = std::move(residuals);
  result.inliers = std::move(inliers);
  result.inlierCount = count;
  return result;
}

}  // namespace mdbrief
