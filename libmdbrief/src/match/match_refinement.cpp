// refineMatches: Lucas-Kanade of b's patch against a's on the keypoints' levels, the patches
// mapped through each camera's tangent-plane Jacobian (match_refinement.hpp).
#include "mdbrief/match/match_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "mdbrief/camera/tangent_plane.hpp"
#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief {

const OptionTable<MatchRefinementOptions>& matchRefinementOptionFields() {
  using O = MatchRefinementOptions;
  using R = FieldRange;
  static const OptionTable<O> table = {
      integerField<O>("patchRadius", "", "patch_radius", "--refine-patch-radius",
                      "half the refinement patch's side, level pixels", R::closed(2, 15),
                      [](auto& o) -> auto& { return o.patchRadius; }),
      integerField<O>("finerLevels", "", "finer_levels", "--refine-finer-levels",
                      "levels finer than the keypoints' to refine on", R::closed(0, 8),
                      [](auto& o) -> auto& { return o.finerLevels; }),
      integerField<O>("maxIterations", "", "max_iterations", "--refine-max-iterations",
                      "Gauss-Newton iterations per level at most", R::closed(1, 100),
                      [](auto& o) -> auto& { return o.maxIterations; }),
      realField<O>("maxShift", "", "max_shift", "--refine-max-shift",
                   "a refinement moving further fails, level pixels of b's keypoint", R::openLow(0, 10),
                   [](auto& o) -> auto& { return o.maxShift; }),
      realField<O>("minEigenvalue", "", "min_eigenvalue", "--refine-min-eigenvalue",
                   "smallest structure tensor eigenvalue of a patch that fixes both directions", R::closed(0, 10),
                   [](auto& o) -> auto& { return o.minEigenvalue; }),
  };
  return table;
}

void validate(const MatchRefinementOptions& options) {
  validateFields(matchRefinementOptionFields(), options, "MatchRefinementOptions");
}

const char* toString(RefinementFailure failure) {
  switch (failure) {
    case RefinementFailure::None:
      return "";
    case RefinementFailure::OutsideImage:
      return "patch outside the image";
    case RefinementFailure::Aperture:
      return "aperture: the patch does not fix both directions";
    case RefinementFailure::Diverged:
      return "diverged";
  }
  return "unknown failure";
}

namespace {

// Bilinear sample of a CV_32F level at (x, y), which the caller keeps inside [0, cols - 1] x
// [0, rows - 1].
float bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), image.cols - 2), y0 = std::min(static_cast<int>(y), image.rows - 2);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(y0 + 1);
  const float top = r0[x0] + fx * (r0[x0 + 1] - r0[x0]);
  const float bottom = r1[x0] + fx * (r1[x0 + 1] - r1[x0]);
  return top + fy * (bottom - top);
}

bool inside(const cv::Mat& image, const cv::Point2d& p, double margin) {
  return p.x >= margin && p.y >= margin && p.x <= image.cols - 1 - margin && p.y <= image.rows - 1 - margin;
}

// Zero mean, unit variance; false for a patch without variance.
bool normalise(std::vector<float>& v, float& deviation) {
  double sum = 0, squares = 0;
  for (float x : v) sum += x, squares += static_cast<double>(x) * x;
  const double n = static_cast<double>(v.size()), mean = sum / n, variance = squares / n - mean * mean;
  if (!(variance > 1e-12)) return false;
  deviation = static_cast<float>(std::sqrt(variance));
  for (float& x : v) x = static_cast<float>((x - mean) / deviation);
  return true;
}

enum class LevelOutcome { Aligned, OutsideImage, Aperture, Diverged };

struct LevelResult {
  LevelOutcome outcome = LevelOutcome::Diverged;
  cv::Point2d shiftInput;  // b's shift, input pixels
  double sigmaLevel = 0;   // along the least certain direction, level pixels of b
};

// Aligns b's patch on level lb with a's on level la, from b's shift `start` (input pixels); a
// shift beyond `maxShift` input pixels diverged.
LevelResult alignOnLevel(const ImagePyramid& pa, int la, const cv::Point2d& pointA, const ImagePyramid& pb, int lb,
                         const cv::Point2d& pointB, const cv::Matx22d& aToB, const cv::Point2d& start, double maxShift,
                         const MatchRefinementOptions& o) {
  LevelResult result;
  const LevelGrid ga = pa.grid(la), gb = pb.grid(lb);
  const cv::Mat& ia = pa.smoothedFloat(la);
  const cv::Mat& ib = pb.smoothedFloat(lb);
  const int r = o.patchRadius, side = 2 * r + 1, count = side * side;
  const cv::Point2d ca = ga.toLevel(pointA), cb = gb.toLevel(pointB);
  if (!inside(ia, ca, r + 1)) {  // the template's gradients read one pixel beyond the patch
    result.outcome = LevelOutcome::OutsideImage;
    return result;
  }
  // a's samples on the level grid around its point; b's at the offsets the cameras map them to
  // (m: a's level pixels to b's).
  const cv::Matx22d m = cv::Matx22d(1 / gb.step.x, 0, 0, 1 / gb.step.y) * aToB * cv::Matx22d(ga.step.x, 0, 0, ga.step.y);
  std::vector<float> templ(count), gx(count), gy(count);
  std::vector<cv::Point2d> offsetB(count);
  for (int v = -r, k = 0; v <= r; ++v)
    for (int u = -r; u <= r; ++u, ++k) {
      const double x = ca.x + u, y = ca.y + v;
      templ[k] = bilinear(ia, x, y);
      gx[k] = 0.5f * (bilinear(ia, x + 1, y) - bilinear(ia, x - 1, y));
      gy[k] = 0.5f * (bilinear(ia, x, y + 1) - bilinear(ia, x, y - 1));
      const cv::Vec2d offset = m * cv::Vec2d(u, v);
      offsetB[k] = {offset[0], offset[1]};
    }
  float deviation = 0;
  if (!normalise(templ, deviation)) {
    result.outcome = LevelOutcome::Aperture;
    return result;
  }
  // Inverse compositional: the Jacobian is the template's gradient carried into b's level pixels
  // (m^-T), the same at every iteration, so each iteration samples b's patch only.
  const cv::Matx22d carry = m.inv().t();
  std::vector<double> jx(count), jy(count);
  double hxx = 0, hxy = 0, hyy = 0;
  for (int k = 0; k < count; ++k) {
    const cv::Vec2d g = carry * cv::Vec2d(gx[k] / deviation, gy[k] / deviation);
    jx[k] = g[0], jy[k] = g[1];
    hxx += jx[k] * jx[k], hxy += jx[k] * jy[k], hyy += jy[k] * jy[k];
  }
  const double trace = hxx + hyy, det = hxx * hyy - hxy * hxy;
  const double smallest = 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4 * det)));
  if (!(smallest / count >= o.minEigenvalue) || !(det > 0)) {
    result.outcome = LevelOutcome::Aperture;
    return result;
  }
  cv::Point2d shift(start.x / gb.step.x, start.y / gb.step.y);  // level pixels of b
  std::vector<float> sample(count);
  double residual = 0;
  for (int iteration = 0; iteration < o.maxIterations; ++iteration) {
    for (int k = 0; k < count; ++k) {
      const cv::Point2d p = cb + shift + offsetB[k];
      if (!inside(ib, p, 0.0)) {
        result.outcome = LevelOutcome::OutsideImage;
        return result;
      }
      sample[k] = bilinear(ib, p.x, p.y);
    }
    float deviationB = 0;
    if (!normalise(sample, deviationB)) {
      result.outcome = LevelOutcome::Aperture;
      return result;
    }
    double bx = 0, by = 0;
    residual = 0;
    for (int k = 0; k < count; ++k) {
      const double e = sample[k] - templ[k];
      bx += jx[k] * e, by += jy[k] * e;
      residual += e * e;
    }
    const cv::Point2d step(-(hyy * bx - hxy * by) / det, -(hxx * by - hxy * bx) / det);
    shift += step;
    if (!(std::hypot(shift.x * gb.step.x, shift.y * gb.step.y) <= maxShift)) {
      result.outcome = LevelOutcome::Diverged;
      return result;
    }
    if (std::hypot(step.x, step.y) < 0.01) {
      result.outcome = LevelOutcome::Aligned;
      break;
    }
  }
  if (result.outcome != LevelOutcome::Aligned) return result;
  result.shiftInput = {shift.x * gb.step.x, shift.y * gb.step.y};
  // The residual's variance per sample through the inverse tensor's largest eigenvalue.
  result.sigmaLevel = std::sqrt(residual / std::max(1, count - 2) / smallest);
  return result;
}

RefinedMatch refineOne(const ImagePyramid& pa, const Camera& cameraA, const cv::KeyPoint& ka, const ImagePyramid& pb,
                       const Camera& cameraB, const cv::KeyPoint& kb, const MatchRefinementOptions& o) {
  RefinedMatch out;
  out.pointB = kb.pt;
  if (!cameraB.pixelToBearing(out.pointB, out.bearingB)) out.bearingB = {0, 0, 0};
  const auto fail = [&](RefinementFailure f) {
    out.failure = f;
    return out;
  };
  const auto frameA = tangentPlaneAt(cameraA, ka.pt, 180.0), frameB = tangentPlaneAt(cameraB, kb.pt, 180.0);
  if (!frameA || !frameB || !(cv::determinant(frameA->jacobian) != 0)) return fail(RefinementFailure::OutsideImage);
  // An offset of a's image maps to the plane, is scaled by the keypoints' size ratio, and maps
  // into b's image.
  const double scale = ka.size > 0 && kb.size > 0 ? static_cast<double>(kb.size) / ka.size : 1.0;
  const cv::Matx22d aToB = frameB->jacobian * scale * frameA->jacobian.inv();
  const int steps = std::min({o.finerLevels, ka.octave, kb.octave});
  const double ownStep = pb.grid(kb.octave).step.x;
  cv::Point2d shift(0, 0);
  double sigmaLevel = 0;
  int level = -1;
  for (int j = 0; j <= steps; ++j) {
    const int lb = kb.octave - j;
    const LevelResult r = alignOnLevel(pa, ka.octave - j, ka.pt, pb, lb, kb.pt, aToB, shift, o.maxShift * ownStep, o);
    if (r.outcome != LevelOutcome::Aligned) {
      if (j > 0) break;  // a finer level that cannot align adds nothing: keep the coarser result
      return fail(r.outcome == LevelOutcome::OutsideImage ? RefinementFailure::OutsideImage
                  : r.outcome == LevelOutcome::Aperture  ? RefinementFailure::Aperture
                                                          : RefinementFailure::Diverged);
    }
    shift = r.shiftInput;
    sigmaLevel = r.sigmaLevel * pb.grid(lb).step.x;
    level = lb;
  }
  cv::Vec3d bearing;
  const cv::Point2d refined = cv::Point2d(kb.pt) + shift;
  if (!cameraB.pixelToBearing(refined, bearing)) return fail(RefinementFailure::OutsideImage);
  out.pointB = refined;
  out.bearingB = bearing / cv::norm(bearing);
  out.sigmaPx = sigmaLevel;
  out.level = level;
  return out;
}

}  // namespace

std::vector<RefinedMatch> refineMatches(const ImagePyramid& pyramidA, const Camera& cameraA,
                                        const std::vector<cv::KeyPoint>& keypointsA, const ImagePyramid& pyramidB,
                                        const Camera& cameraB, const std::vector<cv::KeyPoint>& keypointsB,
                                        const std::vector<cv::DMatch>& matches, const MatchRefinementOptions& options) {
  validate(options);
  // Another size would put each keypoint's ray, and its patch's mapping, elsewhere in the image.
  const auto sameSize = [](const Camera& camera, const ImagePyramid& pyramid, const char* side) {
    if (camera.imageSize() != pyramid.inputSize())
      throw std::invalid_argument("refineMatches: camera" + std::string(side) + "'s image size " +
                                  internal::sizeText(camera.imageSize()) + " differs from pyramid" + side +
                                  "'s input " + internal::sizeText(pyramid.inputSize()));
  };
  sameSize(cameraA, pyramidA, "A");
  sameSize(cameraB, pyramidB, "B");
  const auto check = [](const std::vector<cv::KeyPoint>& kps, const ImagePyramid& pyramid, const char* side) {
    for (size_t k = 0; k < kps.size(); ++k) {
      if (kps[k].octave < 0 || kps[k].octave >= pyramid.levels())
        throw std::invalid_argument("refineMatches: keypoints" + std::string(side) + "[" + std::to_string(k) +
                                    "].octave " + std::to_string(kps[k].octave) + " is no level of its pyramid (0.." +
                                    std::to_string(pyramid.levels() - 1) + ")");
      if (!std::isfinite(kps[k].pt.x) || !std::isfinite(kps[k].pt.y) || !std::isfinite(kps[k].size))
        throw std::invalid_argument("refineMatches: keypoints" + std::string(side) + "[" + std::to_string(k) +
                                    "] has a position or size that is not finite");
    }
  };
  check(keypointsA, pyramidA, "A");
  check(keypointsB, pyramidB, "B");
  for (size_t m = 0; m < matches.size(); ++m)
    if (matches[m].queryIdx < 0 || matches[m].queryIdx >= static_cast<int>(keypointsA.size()) ||
        matches[m].trainIdx < 0 || matches[m].trainIdx >= static_cast<int>(keypointsB.size()))
      throw std::invalid_argument("refineMatches: matches[" + std::to_string(m) + "] (" +
                                  std::to_string(matches[m].queryIdx) + ", " + std::to_string(matches[m].trainIdx) +
                                  ") indexes beyond the keypoints (" + std::to_string(keypointsA.size()) + ", " +
                                  std::to_string(keypointsB.size()) + ")");
  std::vector<RefinedMatch> out(matches.size());
  tbb::parallel_for(size_t(0), matches.size(), [&](size_t m) {
    out[m] = refineOne(pyramidA, cameraA, keypointsA[matches[m].queryIdx], pyramidB, cameraB,
                       keypointsB[matches[m].trainIdx], options);
  });
  return out;
}

}  // namespace mdbrief
