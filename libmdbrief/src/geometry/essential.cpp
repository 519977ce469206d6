// fitEssential: RANSAC over OpenGV's 5-point solver (Nister), the pose factored out of the best
// essential matrix, refined on the inliers by Levenberg-Marquardt on their epipolar angles.
#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/calib3d.hpp>
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
  const cv::Matx33d e = essentialMatrix(pose);
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

// MSAC's score of a labelling (Torr and Zisserman 2000): each inlier's squared residual over the
// threshold's, each outlier 1. Lower is better; unlike the count, it prefers the model that fits
// its inliers closer.
double truncatedCost(const geometry::CheckedMatches& m, const std::vector<double>& residuals,
                     const std::vector<unsigned char>& inliers) {
  double cost = 0;
  for (int k = 0; k < m.size(); ++k) {
    const double e = m.scale.empty() ? residuals[k] / m.maxAngle : residuals[k] * m.scale[k] / m.maxPixels;
    cost += inliers[k] ? e * e : 1.0;
  }
  return cost;
}

// The signed sine of each member's epipolar angle under (r, t), times its pixel scale when the
// threshold is in pixels: the residuals the refinement minimises. Returns their squared sum.
double epipolarResiduals(const geometry::CheckedMatches& m, const std::vector<int>& members, const cv::Matx33d& r,
                         const cv::Vec3d& t, cv::Mat& out) {
  out.create(static_cast<int>(members.size()), 1, CV_64F);
  double* v = out.ptr<double>();
  for (size_t i = 0; i < members.size(); ++i) {
    const int k = members[i];
    // The normal of a's epipolar plane, in a's frame; R b is b in a's frame.
    const cv::Vec3d normal = m.a[k].cross(t);
    const double nn = cv::norm(normal);
    v[i] = nn > 0 ? (r * m.b[k]).dot(normal) / nn : 0.0;
    if (!m.scale.empty()) v[i] *= m.scale[k];
  }
  return out.dot(out);
}

// Levenberg-Marquardt over the pose's five degrees of freedom: a rotation increment w (R =
// exp([w]x) R0) and a step of t in its tangent plane (t = (t0 + s1 e1 + s2 e2) / |...|). Forward
// differences: five residual passes per iteration over a few hundred inliers cost far less
// than OpenGV's optimize_nonlinear (6 ms for 350 inliers), which the benchmark's 5 ms target
// did not leave room for.
RelativePose refinePose(const RelativePose& start, const geometry::CheckedMatches& m, const std::vector<int>& members) {
  const auto apply = [](const RelativePose& p, const double* d) {
    cv::Matx33d increment;
    cv::Rodrigues(cv::Vec3d(d[0], d[1], d[2]), increment);
    const cv::Vec3d& t = p.translation;
    const cv::Vec3d helper = std::abs(t[0]) < 0.9 ? cv::Vec3d(1, 0, 0) : cv::Vec3d(0, 1, 0);
    const cv::Vec3d e1 = cv::normalize(t.cross(helper)), e2 = t.cross(e1);
    return RelativePose{increment * p.rotation, cv::normalize(t + d[3] * e1 + d[4] * e2)};
  };
  const int rows = static_cast<int>(members.size());
  RelativePose pose = start;
  cv::Mat r, trial, jac(rows, 5, CV_64F);
  double cost = epipolarResiduals(m, members, pose.rotation, pose.translation, r), lambda = 1e-3;
  constexpr double kStep = 1e-7;
  for (int iteration = 0; iteration < 30; ++iteration) {
    for (int p = 0; p < 5; ++p) {
      double d[5] = {0, 0, 0, 0, 0};
      d[p] = kStep;
      const RelativePose moved = apply(pose, d);
      epipolarResiduals(m, members, moved.rotation, moved.translation, trial);
      jac.col(p) = (trial - r) / kStep;
    }
    const cv::Mat jtj = jac.t() * jac, jtr = jac.t() * r;
    bool improved = false;
    while (lambda < 1e8) {
      cv::Mat damped = jtj.clone(), step;
      for (int p = 0; p < 5; ++p) damped.at<double>(p, p) *= 1.0 + lambda;
      if (!cv::solve(damped, -jtr, step, cv::DECOMP_CHOLESKY)) break;
      const RelativePose candidate = apply(pose, step.ptr<double>());
      const double c = epipolarResiduals(m, members, candidate.rotation, candidate.translation, trial);
      if (c < cost) {
        improved = cost - c > 1e-10 * cost;
        pose = candidate, cost = c, r = trial.clone(), lambda = std::max(lambda * 0.1, 1e-9);
        break;
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
  return pose;
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
  // |b . n| <= sin(limit) |n| for the normal n = E^T a of a's epipolar plane.
  std::vector<double> sinLimit(n);
  for (int k = 0; k < n; ++k) {
    const double limit = m.scale.empty() ? m.maxAngle : m.maxPixels / m.scale[k];
    sinLimit[k] = limit >= CV_PI / 2 ? 1.0 : std::sin(limit);
  }
  const auto countInliers = [&](const Eigen::Matrix3d& e) {
    int count = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d normal = e.transpose() * fa[k];
      count += std::abs(fb[k].dot(normal)) <= sinLimit[k] * normal.norm();
    }
    return count;
  };

  opengv::relative_pose::CentralRelativeAdapter adapter(fa, fb);
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  // Every model within 10 % of the best count is kept for the choice of pose: a plane's matches
  // fit two essential matrices equally well, and only one puts the plane in front of both
  // cameras (the count of RANSAC cannot tell them apart).
  constexpr double kNearBest = 0.9;
  constexpr size_t kCandidates = 8;
  std::vector<std::pair<int, Eigen::Matrix3d>> candidates;
  int bestCount = 0, needed = options.maxIterations, models = 0, done = 0;
  std::vector<int> sample(kSample);
  const auto sampleUpTo = [&] {
    for (; done < needed; ++done) {
      if (options.interruptCheck) options.interruptCheck();
      for (int s = 0; s < kSample; ++s) {
        do sample[s] = pick(rng);
        while (std::find(sample.begin(), sample.begin() + s, sample[s]) != sample.begin() + s);
      }
      // Up to 10 essential matrices per sample, each scored.
      for (const auto& e : opengv::relative_pose::fivept_nister(adapter, sample)) {
        if (!e.allFinite()) continue;
        ++models;
        const int count = countInliers(e);
        if (count < kNearBest * bestCount) continue;
        candidates.emplace_back(count, e);
        if (count > bestCount) {
          bestCount = count;
          needed = std::min(needed, ransacIterationsNeeded(static_cast<double>(count) / n, kSample,
                                                           options.confidence, options.maxIterations));
        }
        if (candidates.size() > 4 * kCandidates) {
          // Best first, earliest first among equals: the same order on every run.
          std::stable_sort(candidates.begin(), candidates.end(),
                           [](const auto& x, const auto& y) { return x.first > y.first; });
          candidates.resize(kCandidates);
        }
      }
    }
  };

  // E = [t]x R factors into four poses; of every candidate's, the one that puts most matches
  // within the threshold in front of both cameras.
  Eigen::Matrix3d w;
  w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  std::vector<double> residuals;
  std::vector<unsigned char> inliers;
  RelativePose pose;
  int poseCount = -1;
  const double parallel = m.typicalAngle();
  std::vector<int> epipolar;
  const auto choosePose = [&] {
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const auto& x, const auto& y) { return x.first > y.first; });
    if (candidates.size() > kCandidates) candidates.resize(kCandidates);
    poseCount = -1;
    for (const auto& [epipolarCount, e] : candidates) {
      if (epipolarCount < kNearBest * bestCount) continue;
      epipolar.clear();
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d normal = e.transpose() * fa[k];
        if (std::abs(fb[k].dot(normal)) <= sinLimit[k] * normal.norm()) epipolar.push_back(k);
      }
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(e, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
      if (u.determinant() < 0) u = -u;
      if (v.determinant() < 0) v = -v;
      for (const Eigen::Matrix3d& r :
           {Eigen::Matrix3d(u * w * v.transpose()), Eigen::Matrix3d(u * w.transpose() * v.transpose())})
        for (const Eigen::Vector3d& t : {Eigen::Vector3d(u.col(2)), Eigen::Vector3d(-u.col(2))}) {
          const RelativePose candidate{toCv(r), cv::Vec3d(t[0], t[1], t[2])};
          int count = 0;
          for (int k : epipolar)
            count += geometry::inFront(candidate.rotation, candidate.translation, m.a[k], m.b[k], parallel);
          if (count > poseCount) poseCount = count, pose = candidate;
        }
    }
  };
  // RANSAC stops when the best epipolar count says enough samples were drawn. On a plane that
  // count misleads: a twin of the true essential matrix explains the plane's matches as well and
  // puts part of them behind a camera, and a few samples may have drawn only the twin (a rendered
  // plane: 506 of 757 inliers on one seed in four). So the count the pose keeps in front decides
  // again how many samples are needed, and sampling goes on until it is satisfied.
  for (;;) {
    sampleUpTo();
    if (bestCount < kSample) {
      geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
      return result;
    }
    choosePose();
    const int stillNeeded = ransacIterationsNeeded(static_cast<double>(std::max(poseCount, 0)) / n, kSample,
                                                   options.confidence, options.maxIterations);
    if (stillNeeded <= done) break;
    needed = stillNeeded;
  }
  int count = label(m, pose, options.inFront, residuals, inliers);

  // Refined on the inliers, relabelled, and again while that adds inliers (a minimal sample's
  // model is noisy, so its inliers are only part of the refined model's).
  for (int round = 0; options.refine && count >= kSample && round < 5; ++round) {
    std::vector<int> members;
    for (int k = 0; k < n; ++k)
      if (inliers[k]) members.push_back(k);
    const RelativePose candidate = refinePose(pose, m, members);
    std::vector<double> refinedResiduals;
    std::vector<unsigned char> refinedInliers;
    const int refinedCount = label(m, candidate, options.inFront, refinedResiduals, refinedInliers);
    // The refinement minimises the inliers' squared errors, so a borderline inlier may move past
    // the threshold; the count would then keep the minimal sample's pose, degrees off on a
    // rendered stereo pair with 600 inliers within 0.1 px. Kept unless its MSAC score is worse.
    if (truncatedCost(m, refinedResiduals, refinedInliers) > truncatedCost(m, residuals, inliers)) break;
    const bool relabelled = refinedInliers != inliers;
    pose = candidate, count = refinedCount;
    residuals.swap(refinedResiduals);
    inliers.swap(refinedInliers);
    if (!relabelled) break;
  }
  if (count < kSample) {
    geometry::fail(result, TwoViewFailure::NoModel, n, kSample);
    return result;
  }
  result.pose = pose;
  result.essential = essentialMatrix(pose);
  result.residuals = std::move(residuals);
  result.inliers = std::move(inliers);
  result.inlierCount = count;
  // Would random matches give as many inliers? A bearing lies within angle x of a plane with
  // probability sin x when bearings spread over the sphere.
  const double chance = geometry::chanceShare(n, options.seed, std::sin(parallel), [&](int ka, int kb) {
    const double r = geometry::epipolarResidual(result.essential, m.a[ka], m.b[kb]);
    return m.within(kb, r) &&
           (!options.inFront || geometry::inFront(pose.rotation, pose.translation, m.a[ka], m.b[kb], parallel));
  });
  result.log10FalseAlarms = geometry::significanceLog10(models, n, std::min(count, bestCount), kSample, chance);
  geometry::failIfChance(result, options.maxFalseAlarms, n, kSample);
  if (!result.ok()) result.pose = {}, result.essential = cv::Matx33d();
  return result;
}

}  // namespace mdbrief
