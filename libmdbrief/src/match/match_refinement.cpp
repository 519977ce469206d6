// refineMatches: Lucas-Kanade of b's patch against a's on the keypoints' levels, the patches
// mapped through each camera's tangent-plane Jacobian (match_refinement.hpp).
#include "mdbrief/match/match_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
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
      realField<O>("smoothingSigma", "", "smoothing_sigma", "--refine-smoothing-sigma",
                   "the Gaussian the levels are smoothed by before alignment, level pixels",
                   R::openLow(0, ImagePyramid::kMaxFloatSigma), [](auto& o) -> auto& { return o.smoothingSigma; }),
      integerField<O>("finerLevels", "", "finer_levels", "--refine-finer-levels",
                      "levels finer than the keypoints' to refine on", R::closed(0, 16),
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
      realField<O>("maxSigmaPx", "", "max_sigma_px", "--refine-max-sigma-px",
                   "a refined point less certain than this (its standard deviation, input pixels) fails",
                   R::openLow(0, 100), [](auto& o) -> auto& { return o.maxSigmaPx; }),
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
    case RefinementFailure::Uncertain:
      return "uncertain: its standard deviation exceeds maxSigmaPx";
  }
  return "unknown failure";
}

namespace {

// Four floats, one lane each: GCC and Clang give SSE or NEON, the same sums on both (the library
// builds with -ffp-contract=off).
typedef float Lanes __attribute__((vector_size(16)));

// A CV_32F level's pixels and size, as the samples read them. Reading them so, sharing the
// template's weights, and sampling patches well inside a level unchecked (cubic<true>) take the
// refinement from 22.4-23.1 to 19.6-20.8 us per match (BM_RefineMatches) with the same bits.
struct Level {
  const float* pixels;
  size_t stride;  // floats per row
  int cols, rows;
  explicit Level(const cv::Mat& image)
      : pixels(image.ptr<float>()), stride(image.step1()), cols(image.cols), rows(image.rows) {}
  const float* row(int y) const { return pixels + stride * static_cast<size_t>(y); }
};

// Keys' cubic convolution weights (a = -1/2) of the four samples around a fraction t in [0, 1),
// by Horner's rule in four lanes.
inline __attribute__((always_inline)) Lanes cubicWeights(float t) {
  const Lanes a{-0.5f, 1.5f, -1.5f, 0.5f}, b{1.0f, -2.5f, 2.0f, -0.5f}, c{-0.5f, 0.0f, 0.5f, 0.0f},
      d{0.0f, 1.0f, 0.0f, 0.0f};
  return ((a * t + b) * t + c) * t + d;
}

// Rows y..y + 3 of columns x..x + 3, weighed by w and summed per column (four lanes at once).
inline __attribute__((always_inline)) Lanes weighedRows(const Level& image, int x, int y, Lanes w) {
  Lanes sum{0, 0, 0, 0};
  for (int j = 0; j < 4; ++j) {
    Lanes row;
    std::memcpy(&row, image.row(y + j) + x, sizeof row);
    sum += w[j] * row;
  }
  return sum;
}

// The sample between pixels (x0, y0) and (x0 + 1, y0 + 1) with weights wx, wy over columns
// x0 - 1..x0 + 2 and rows y0 - 1..y0 + 2, all in the level.
inline __attribute__((always_inline)) float weighedSample(const Level& image, int x0, int y0, Lanes wx, Lanes wy) {
  const Lanes products = wx * weighedRows(image, x0 - 1, y0 - 1, wy);
  return (products[0] + products[1]) + (products[2] + products[3]);
}

// Cubic sample of a CV_32F level at (x, y), which the caller keeps inside [0, cols - 1] x
// [0, rows - 1]; the samples beyond the level repeat its edge. Cubic, not bilinear: the samples
// of a patch turned or scaled against a's fall at every fraction between pixels, and a bilinear
// sample blurs by its fraction, so b's samples differ from a's by more than the motion. A texture
// turned 3 degrees: error p90 0.024 -> 0.014 px (tests/test_match_refinement.cpp); the stereo
// benchmark: EuRoC's residual 0.084 / 0.287 -> 0.081 / 0.280 px, the rendered rig's RMS 0.168 ->
// 0.164 px; 16.2 -> 20.4 us per match (BM_RefineMatches, avx2). Inlined: GCC kept the bilinear
// sample a call per sample, a third of the refinement's time (perf).
// `interior`: the caller knows that x, y >= 1 and x < cols - 2, y < rows - 2, so that the four
// by four samples are all in the level.
template <bool interior>
inline __attribute__((always_inline)) float cubic(const Level& image, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), image.cols - 2), y0 = std::min(static_cast<int>(y), image.rows - 2);
  const Lanes wx = cubicWeights(static_cast<float>(x - x0)), wy = cubicWeights(static_cast<float>(y - y0));
  if (interior || (x0 >= 1 && y0 >= 1 && x0 + 2 < image.cols && y0 + 2 < image.rows))
    return weighedSample(image, x0, y0, wx, wy);
  Lanes columns{0, 0, 0, 0};
  for (int j = 0; j < 4; ++j) {
    const float* row = image.row(std::clamp(y0 - 1 + j, 0, image.rows - 1));
    const auto at = [&](int x) { return row[std::clamp(x, 0, image.cols - 1)]; };
    columns += wy[j] * Lanes{at(x0 - 1), at(x0), at(x0 + 1), at(x0 + 2)};
  }
  const Lanes products = wx * columns;
  return (products[0] + products[1]) + (products[2] + products[3]);
}

bool inside(const Level& image, const cv::Point2d& p, double margin) {
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

// The derivative of a normalised patch (normalise()) from its samples' derivatives: a motion
// that changes every sample alike, or scales the patch's contrast, leaves it as it is. Each
// column loses its mean and its component along the normalised patch `unit`. Without this, a
// patch on an intensity ramp counts the ramp as information: its steps fall short along the
// ramp and creep towards the minimum (on the stereo benchmark, one match in twelve did not
// settle in ten iterations per level), and its standard deviation comes out too small.
void normalisedDerivative(std::vector<cv::Vec4d>& j, const std::vector<float>& unit) {
  const double n = static_cast<double>(j.size());
  cv::Vec4d mean(0, 0, 0, 0), along(0, 0, 0, 0);
  for (size_t k = 0; k < j.size(); ++k) mean += j[k], along += j[k] * static_cast<double>(unit[k]);
  mean *= 1 / n, along *= 1 / n;  // unit's squares sum to n
  for (size_t k = 0; k < j.size(); ++k) j[k] -= mean + along * static_cast<double>(unit[k]);
}

// The smaller eigenvalue of a symmetric 2x2 matrix.
double smallerEigenvalue(const cv::Matx22d& a) {
  const double trace = a(0, 0) + a(1, 1), det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  return 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4 * det)));
}

enum class LevelOutcome { Aligned, OutsideImage, Aperture, Diverged };

// b's patch against a's: turned and scaled on the tangent plane about its centre, then shifted.
struct Alignment {
  cv::Point2d shift;    // b's point moved by, input pixels
  double turn = 0;      // radians, the plane's x axis towards its y axis
  double logScale = 0;  // b's patch scaled by exp(logScale) beyond the keypoints' size ratio
};

struct LevelResult {
  LevelOutcome outcome = LevelOutcome::Diverged;
  Alignment alignment;
  double sigmaLevel = 0;  // along the least certain direction, level pixels of b
};

cv::Matx22d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c, -s, s, c};
}

// Turn and scale are kept where together they exceed this many standard deviations (their
// Mahalanobis length, from the residual). Chosen for the turn alone: on pairs that did not roll
// (the rendered plane of the tests, Oxford's ubc and bikes) nine patches in ten stayed below it,
// the rest turned by the model's errors rather than the residual's noise; of the patches rolled 2
// and 5 degrees (the guide's scene) 85 and 96 % exceeded it.
constexpr double kShapeSignificance = 8.0;

// The keypoints' size ratio is off by a few tens of percent at most on right matches; a scale
// that runs beyond a factor of two is the alignment leaving the point.
const double kMaxLogScale = std::log(2.0);

// Aligns b's patch on level lb with a's on level la, from `start`; a shift beyond `maxShift`
// input pixels diverged. aToPlane: a's input pixels to plane units; planeToB: plane units to b's
// input pixels (the size ratio included). Without estimateShape, start's turn and scale are held.
LevelResult alignOnLevel(const ImagePyramid& pa, int la, const cv::Point2d& pointA, const ImagePyramid& pb, int lb,
                         const cv::Point2d& pointB, const cv::Matx22d& aToPlane, const cv::Matx22d& planeToB,
                         const Alignment& start, double maxShift, const MatchRefinementOptions& o, bool estimateShape) {
  LevelResult result;
  const LevelGrid ga = pa.grid(la), gb = pb.grid(lb);
  const Level ia(pa.smoothedFloat(la, o.smoothingSigma)), ib(pb.smoothedFloat(lb, o.smoothingSigma));
  const int r = o.patchRadius, side = 2 * r + 1, count = side * side;
  const cv::Point2d ca = ga.toLevel(pointA), cb = gb.toLevel(pointB);
  if (!inside(ia, ca, r + 1)) {  // the template's gradients read one pixel beyond the patch
    result.outcome = LevelOutcome::OutsideImage;
    return result;
  }
  // a's samples on the patch's grid and a pixel around it, once: the gradients are their
  // central differences.
  const int wide = side + 2;
  std::vector<float> grid(static_cast<size_t>(wide) * wide);
  if (ca.x - r - 1 >= 1 && ca.y - r - 1 >= 1 && ca.x + r + 1 < ia.cols - 2 && ca.y + r + 1 < ia.rows - 2) {
    // Whole pixels apart, the samples share their weights.
    const int x0 = static_cast<int>(ca.x), y0 = static_cast<int>(ca.y);
    const Lanes wx = cubicWeights(static_cast<float>(ca.x - x0)), wy = cubicWeights(static_cast<float>(ca.y - y0));
    for (int v = -r - 1, k = 0; v <= r + 1; ++v)
      for (int u = -r - 1; u <= r + 1; ++u, ++k) grid[k] = weighedSample(ia, x0 + u, y0 + v, wx, wy);
  } else {
    for (int v = -r - 1, k = 0; v <= r + 1; ++v)
      for (int u = -r - 1; u <= r + 1; ++u, ++k) grid[k] = cubic<false>(ia, ca.x + u, ca.y + v);
  }
  std::vector<float> templ(count), gx(count), gy(count);
  for (int v = 0, k = 0; v < side; ++v)
    for (int u = 0; u < side; ++u, ++k) {
      const float* row = &grid[static_cast<size_t>(v + 1) * wide + u + 1];
      templ[k] = row[0];
      gx[k] = 0.5f * (row[1] - row[-1]);
      gy[k] = 0.5f * (row[wide] - row[-wide]);
    }
  float deviation = 0;
  if (!normalise(templ, deviation)) {
    result.outcome = LevelOutcome::Aperture;
    return result;
  }
  // b's sample of a's level pixel offset x: cb + shift + fromPlane R(turn) toPlane x.
  const cv::Matx22d toPlane = aToPlane * cv::Matx22d(ga.step.x, 0, 0, ga.step.y);
  const cv::Matx22d fromPlane = cv::Matx22d(1 / gb.step.x, 0, 0, 1 / gb.step.y) * planeToB;
  const cv::Matx22d intoPlane = fromPlane.inv();
  // Inverse compositional: the increment turns and shifts a's patch on the plane, so its Jacobian
  // is the template's gradient times the increment's motion of each sample, the same at every
  // iteration; each iteration samples b's patch only. The shift is counted in b's level pixels
  // (m^-T carries a's gradient there); the turn moves a's offset x by the rotation's generator
  // carried into a's level pixels.
  const cv::Matx22d m = fromPlane * toPlane;
  const cv::Matx22d carry = m.inv().t();
  const cv::Matx22d generator = toPlane.inv() * cv::Matx22d(0, -1, 1, 0) * toPlane;
  // The turn and the scale: columns 2 and 3. A scale's generator is the identity, in any frame.
  std::vector<cv::Vec4d> jacobian(count);
  cv::Matx44d h = cv::Matx44d::zeros();
  // The squared level pixels a turn of a radian, or a log scale of one, moves the samples by, summed.
  double turnSpread = 0, scaleSpread = 0;
  for (int v = -r, k = 0; v <= r; ++v)
    for (int u = -r; u <= r; ++u, ++k) {
      const cv::Vec2d g(gx[k] / deviation, gy[k] / deviation), x(u, v);
      const cv::Vec2d gShift = carry * g, motion = generator * x;
      jacobian[k] = {gShift[0], gShift[1], g.dot(motion), g.dot(x)};
      turnSpread += motion.dot(motion);
      scaleSpread += x.dot(x);
    }
  normalisedDerivative(jacobian, templ);
  for (const cv::Vec4d& j : jacobian) h += j * j.t();
  const double hxx = h(0, 0), hxy = h(0, 1), hyy = h(1, 1), det = hxx * hyy - hxy * hxy;
  if (!(smallerEigenvalue({hxx, hxy, hxy, hyy}) / count >= o.minEigenvalue) || !(det > 0)) {
    result.outcome = LevelOutcome::Aperture;
    return result;
  }
  // What the patch tells of the turn and the scale once the shift is fitted (h's Schur
  // complement), per squared level pixel of the samples' motion, is held to the shift's standard:
  // a patch as round as a disc does not fix its turn, nor a patch of parallel stripes its scale.
  const cv::Matx22d shiftInverse = cv::Matx22d(hyy, -hxy, -hxy, hxx) * (1 / det);
  const cv::Matx22d coupling(h(0, 2), h(0, 3), h(1, 2), h(1, 3));
  const cv::Matx22d pull = shiftInverse * coupling;
  const cv::Matx22d shapeInformation = cv::Matx22d(h(2, 2), h(2, 3), h(3, 2), h(3, 3)) - coupling.t() * pull;
  const cv::Matx22d perSpread = cv::Matx22d::diag({1 / std::sqrt(turnSpread), 1 / std::sqrt(scaleSpread)});
  const cv::Matx22d shapePerSpread = perSpread * shapeInformation * perSpread;
  const bool shapeFixed =
      cv::determinant(shapePerSpread) > 0 && smallerEigenvalue(shapePerSpread) >= o.minEigenvalue;
  const cv::Matx22d shapeInverse = shapeFixed ? shapeInformation.inv() : cv::Matx22d::zeros();
  // The patch's half side in b's level pixels: a turn's or a scale's step settles when it moves
  // the patch's edge as little as a shift's step must move its centre.
  const double edge = r * std::sqrt(std::abs(cv::determinant(m)));
  std::vector<float> sample(count);
  // Gauss-Newton from `from`, the turn and scale estimated or held; significance: the squared
  // Mahalanobis length, in the residual's noise, of the turn and log scale (estimated) or of the
  // step they would take (held).
  const auto align = [&](const Alignment& from, bool shaping, double& significance) {
    LevelResult out;
    // h^-1 by blocks, or its shift block alone with the turn and scale held.
    cv::Matx44d inverse = cv::Matx44d::zeros();
    const cv::Matx22d shiftBlock = shaping ? shiftInverse + pull * shapeInverse * pull.t() : shiftInverse;
    const cv::Matx22d cross = -pull * shapeInverse;
    for (int i = 0; i < 2; ++i)
      for (int l = 0; l < 2; ++l) {
        inverse(i, l) = shiftBlock(i, l);
        if (!shaping) continue;
        inverse(i, 2 + l) = inverse(2 + l, i) = cross(i, l);
        inverse(2 + i, 2 + l) = shapeInverse(i, l);
      }
    cv::Point2d shift(from.shift.x / gb.step.x, from.shift.y / gb.step.y);  // level pixels of b
    double turn = from.turn, logScale = from.logScale, residual = 0;
    cv::Vec4d b;
    for (int iteration = 0; iteration < o.maxIterations; ++iteration) {
      const cv::Matx22d warp = fromPlane * (std::exp(logScale) * rotation(turn)) * toPlane;
      const cv::Point2d centre = cb + shift;
      // The warp is affine: its corners bound the patch. Inside the level by a pixel and more
      // (half a pixel more for the samples' rounding), every sample's neighbours are in it, and
      // no sample is checked.
      const cv::Vec2d halfU = warp * cv::Vec2d(r, 0), halfV = warp * cv::Vec2d(0, r);
      const double reachX = std::abs(halfU[0]) + std::abs(halfV[0]) + 0.5,
                   reachY = std::abs(halfU[1]) + std::abs(halfV[1]) + 0.5;
      if (centre.x - reachX >= 1 && centre.y - reachY >= 1 && centre.x + reachX < ib.cols - 2 &&
          centre.y + reachY < ib.rows - 2) {
        for (int v = -r, k = 0; v <= r; ++v)
          for (int u = -r; u <= r; ++u, ++k) {
            const cv::Vec2d offset = warp * cv::Vec2d(u, v);
            sample[k] = cubic<true>(ib, centre.x + offset[0], centre.y + offset[1]);
          }
      } else {
        for (int v = -r, k = 0; v <= r; ++v)
          for (int u = -r; u <= r; ++u, ++k) {
            const cv::Vec2d offset = warp * cv::Vec2d(u, v);
            const cv::Point2d p(centre.x + offset[0], centre.y + offset[1]);
            if (!inside(ib, p, 0.0)) {
              out.outcome = LevelOutcome::OutsideImage;
              return out;
            }
            sample[k] = cubic<false>(ib, p.x, p.y);
          }
      }
      float deviationB = 0;
      if (!normalise(sample, deviationB)) {
        out.outcome = LevelOutcome::Aperture;
        return out;
      }
      b = cv::Vec4d(0, 0, 0, 0);
      residual = 0;
      for (int k = 0; k < count; ++k) {
        const double e = sample[k] - templ[k];
        b += jacobian[k] * e;
        residual += e * e;
      }
      const cv::Vec4d delta = inverse * b;
      // The warp composed with the increment's inverse: turned and scaled back, then shifted back
      // along the plane's axes as the warp now turns and scales them.
      turn -= delta[2];
      logScale -= delta[3];
      const cv::Vec2d back =
          fromPlane * (std::exp(logScale) * rotation(turn)) * intoPlane * cv::Vec2d(delta[0], delta[1]);
      shift -= cv::Point2d(back[0], back[1]);
      // Diverged: too far, or a patch scaled by more than twice the keypoints' size ratio.
      if (!(std::hypot(shift.x * gb.step.x, shift.y * gb.step.y) <= maxShift) || !(std::abs(logScale) <= kMaxLogScale))
        return out;
      if (std::hypot(back[0], back[1]) < 0.01 && std::max(std::abs(delta[2]), std::abs(delta[3])) * edge < 0.01) {
        out.outcome = LevelOutcome::Aligned;
        break;
      }
    }
    if (out.outcome != LevelOutcome::Aligned) return out;  // did not settle
    out.alignment = {{shift.x * gb.step.x, shift.y * gb.step.y}, turn, logScale};
    // The residual's variance per sample through the largest eigenvalue of the shift's covariance
    // (with the turn and scale estimated, their uncertainty included).
    const double variance = residual / std::max(1, count - (shaping ? 4 : 2));
    const double cxx = shiftBlock(0, 0), cxy = shiftBlock(0, 1), cyy = shiftBlock(1, 1);
    const double largest = 0.5 * (cxx + cyy + std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy));
    out.sigmaLevel = std::sqrt(variance * largest);
    const cv::Vec2d step = shaping ? cv::Vec2d(turn, logScale)
                                   : cv::Vec2d(shapeInverse * (cv::Vec2d(b[2], b[3]) - pull.t() * cv::Vec2d(b[0], b[1])));
    significance = variance > 0 ? step.dot(shapeInformation * step) / variance : 0;
    return out;
  };
  double significance = 0;
  if (!shapeFixed || !estimateShape) return align(start, false, significance);
  // Estimating the turn and scale costs the shift precision wherever they move the same samples
  // (the tests' rendered plane, which did not roll: median error 0.068 -> 0.072 px), so they are
  // kept only where they stand out of their noise; otherwise the shift is fitted alone, the patch
  // unturned at the keypoints' size ratio, from where the other fit put it. Where that one does
  // not settle, the shift alone stands if it sees no turn or scale either.
  const double threshold = kShapeSignificance * kShapeSignificance;
  const LevelResult shaped = align(start, true, significance);
  if (shaped.outcome == LevelOutcome::Aligned && significance > threshold) return shaped;
  const Alignment plain{shaped.outcome == LevelOutcome::Aligned ? shaped.alignment.shift : start.shift, 0.0, 0.0};
  const LevelResult held = align(plain, false, significance);
  if (held.outcome == LevelOutcome::Aligned && (shaped.outcome == LevelOutcome::Aligned || significance <= threshold))
    return held;
  return shaped;
}

// The keypoints' orientations are too noisy to turn the patch by: on stereo pairs that did not
// roll (EuRoC, MYNT) those of right matches differ by 2.7 degrees at the median, 10 at the 90th
// percentile. From a turn of zero the alignment finds rolls up to about 10 degrees: the guide's
// scene rolled 5 / 10 / 12 / 20 / 30 degrees keeps 637 / 623 / 592 / 562 / 485 right matches
// refined, 635 / 627 / 611 / 615 / 598 from the orientations' difference. So the turn starts at
// that difference only beyond its noise.
constexpr double kOrientationNoiseDeg = 10.0;

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
  const cv::Matx22d aToPlane = frameA->jacobian.inv(), planeToB = frameB->jacobian * scale;
  Alignment alignment;
  if (ka.angle >= 0 && kb.angle >= 0) {
    const double difference = std::remainder(
        imageAngleToPlaneAngle(frameB->jacobian, kb.angle) - imageAngleToPlaneAngle(frameA->jacobian, ka.angle), 360.0);
    if (std::abs(difference) > kOrientationNoiseDeg) alignment.turn = difference * CV_PI / 180.0;
  }
  const int steps = std::min({o.finerLevels, ka.octave, kb.octave});
  const double ownStep = pb.grid(kb.octave).step.x;
  double sigmaLevel = 0;
  int level = -1;
  for (int j = 0; j <= steps; ++j) {
    const int lb = kb.octave - j;
    const LevelResult r =
        alignOnLevel(pa, ka.octave - j, ka.pt, pb, lb, kb.pt, aToPlane, planeToB, alignment, o.maxShift * ownStep, o, j == 0);
    if (r.outcome != LevelOutcome::Aligned) {
      if (j > 0) break;  // a finer level that cannot align adds nothing: keep the coarser result
      return fail(r.outcome == LevelOutcome::OutsideImage ? RefinementFailure::OutsideImage
                  : r.outcome == LevelOutcome::Aperture  ? RefinementFailure::Aperture
                                                          : RefinementFailure::Diverged);
    }
    alignment = r.alignment;
    sigmaLevel = r.sigmaLevel * pb.grid(lb).step.x;
    level = lb;
  }
  if (!(sigmaLevel <= o.maxSigmaPx)) return fail(RefinementFailure::Uncertain);
  cv::Vec3d bearing;
  const cv::Point2d refined = cv::Point2d(kb.pt) + alignment.shift;
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
