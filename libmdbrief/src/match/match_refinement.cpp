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

// b's patch against a's: mapped on the tangent plane about its centre by `shape`, then shifted.
struct Alignment {
  cv::Point2d shift;                        // b's point moved by, input pixels
  cv::Matx22d shape = cv::Matx22d::eye();  // beyond the keypoints' size ratio, on the plane
};

// The motions of b's patch on the plane beyond a shift: turn and scale (views rolled about the
// viewing direction, sizes misstated), then stretch along x against y and shear, which a surface
// slanted against both views adds: each view foreshortens it by its own angle. Each squares to 2
// under the Frobenius product.
constexpr int kShapes = 4;
const cv::Matx22d kGenerators[kShapes] = {{0, -1, 1, 0}, {1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0}};
// The patch's parameters: b's shift (two), then the shapes' coefficients.
constexpr int kParameters = 2 + kShapes;
using ParameterVector = cv::Vec<double, kParameters>;
using ParameterMatrix = cv::Matx<double, kParameters, kParameters>;

// The derivative of a normalised patch (normalise()) from its samples' derivatives: a motion
// that changes every sample alike, or scales the patch's contrast, leaves it as it is. Each
// column loses its mean and its component along the normalised patch `unit`. Without this, a
// patch on an intensity ramp counts the ramp as information: its steps fall short along the
// ramp and creep towards the minimum (on the stereo benchmark, one match in twelve did not
// settle in ten iterations per level), and its standard deviation comes out too small.
// Only the first `columns` are used.
void normalisedDerivative(std::vector<ParameterVector>& j, const std::vector<float>& unit, int columns) {
  const double n = static_cast<double>(j.size());
  ParameterVector mean = ParameterVector::all(0), along = ParameterVector::all(0);
  for (size_t k = 0; k < j.size(); ++k)
    for (int i = 0; i < columns; ++i) mean[i] += j[k][i], along[i] += j[k][i] * static_cast<double>(unit[k]);
  mean *= 1 / n, along *= 1 / n;  // unit's squares sum to n
  for (size_t k = 0; k < j.size(); ++k)
    for (int i = 0; i < columns; ++i) j[k][i] -= mean[i] + along[i] * static_cast<double>(unit[k]);
}

// The smaller eigenvalue of a symmetric 2x2 matrix.
double smallerEigenvalue(const cv::Matx22d& a) {
  const double trace = a(0, 0) + a(1, 1), det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  return 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4 * det)));
}

// The Cholesky factor l of a symmetric matrix a (a = l l^T); false where a is not positive
// definite. Here, not cv::Matx::inv, whose LU for more than 3 x 3 runs in the OpenCV library,
// compiled elsewhere: this file's arithmetic gives the same bits on every architecture.
template <int n>
bool cholesky(const cv::Matx<double, n, n>& a, cv::Matx<double, n, n>& l) {
  l = cv::Matx<double, n, n>::zeros();
  for (int j = 0; j < n; ++j) {
    double pivot = a(j, j);
    for (int k = 0; k < j; ++k) pivot -= l(j, k) * l(j, k);
    if (!(pivot > 0)) return false;
    l(j, j) = std::sqrt(pivot);
    for (int i = j + 1; i < n; ++i) {
      double v = a(i, j);
      for (int k = 0; k < j; ++k) v -= l(i, k) * l(j, k);
      l(i, j) = v / l(j, j);
    }
  }
  return true;
}

// Whether every eigenvalue of the symmetric matrix a is at least `floor`.
template <int n>
bool eigenvaluesAtLeast(const cv::Matx<double, n, n>& a, double floor) {
  cv::Matx<double, n, n> l;
  return cholesky<n>(a - floor * cv::Matx<double, n, n>::eye(), l);
}

// The inverse of a symmetric positive definite matrix, (l l^T)^-1 = l^-T l^-1; zero where a is
// not positive definite.
template <int n>
cv::Matx<double, n, n> inversePositiveDefinite(const cv::Matx<double, n, n>& a) {
  cv::Matx<double, n, n> l, inverseL = cv::Matx<double, n, n>::zeros();
  if (!cholesky<n>(a, l)) return inverseL;
  for (int j = 0; j < n; ++j) {  // forward substitution, column by column of the identity
    inverseL(j, j) = 1 / l(j, j);
    for (int i = j + 1; i < n; ++i) {
      double v = 0;
      for (int k = j; k < i; ++k) v -= l(i, k) * inverseL(k, j);
      inverseL(i, j) = v / l(i, i);
    }
  }
  return inverseL.t() * inverseL;
}

// The singular values of a 2x2 matrix, largest first.
cv::Vec2d singularValues(const cv::Matx22d& m) {
  const double squares = m(0, 0) * m(0, 0) + m(0, 1) * m(0, 1) + m(1, 0) * m(1, 0) + m(1, 1) * m(1, 1);
  const double det = cv::determinant(m), root = std::sqrt(std::max(0.0, squares * squares - 4 * det * det));
  return {std::sqrt(0.5 * (squares + root)), std::sqrt(std::max(0.0, 0.5 * (squares - root)))};
}

enum class LevelOutcome { Aligned, OutsideImage, Aperture, Diverged };

struct LevelResult {
  LevelOutcome outcome = LevelOutcome::Diverged;
  Alignment alignment;
  double sigmaLevel = 0;  // along the least certain direction, level pixels of b
};

cv::Matx22d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c, -s, s, c};
}

// A shape is kept where its coefficients together exceed this many standard deviations (their
// Mahalanobis length, from the residual). Chosen for the turn alone: on pairs that did not roll
// (the rendered plane of the tests, Oxford's ubc and bikes) nine patches in ten stayed below it,
// the rest turned by the model's errors rather than the residual's noise; of the patches rolled 2
// and 5 degrees (the guide's scene) 85 and 96 % exceeded it.
constexpr double kShapeSignificance = 8.0;

// The keypoints' size ratio is off by a few tens of percent at most on right matches; a shape
// that scales the patch beyond a factor of two along any direction is the alignment leaving the
// point.
constexpr double kMaxScale = 2.0;

// What the patch on one level tells of b's shift and of the first `shapes` shape coefficients.
// `shapes` is 2 (turn and scale) or 4 (all).
template <int shapes>
struct ShapeSystem {
  using Square = cv::Matx<double, shapes, shapes>;
  cv::Matx<double, 2, shapes> pull;  // the shift's response to the shape, shiftInverse * coupling
  Square information;                // once the shift is fitted: h's Schur complement
  Square inverse;                    // information's inverse where fixed, else zero
  bool fixed = false;                // the patch fixes every one of these shapes
};

// One level's alignment: a's template with its derivatives, and b's level to sample.
class LevelAlignment {
 public:
  LevelAlignment(const Level& b, const cv::Point2d& centreB, const std::vector<float>& templ,
                 const std::vector<ParameterVector>& jacobian, const ParameterMatrix& h, const double spread[kShapes],
                 const cv::Matx22d& toPlane, const cv::Matx22d& fromPlane, const cv::Matx22d& startShape,
                 const LevelGrid& gridB, int radius, double maxShift, const MatchRefinementOptions& o, int columns)
      : b_(b), cb_(centreB), templ_(templ), jacobian_(jacobian), columns_(columns), toPlane_(toPlane),
        fromPlane_(fromPlane), back_(startShape.inv() * fromPlane.inv()), gb_(gridB), r_(radius), maxShift_(maxShift),
        o_(o), sample_(templ.size()) {
    const double hxx = h(0, 0), hxy = h(0, 1), hyy = h(1, 1);
    shiftInverse_ = cv::Matx22d(hyy, -hxy, -hxy, hxx) * (1 / (hxx * hyy - hxy * hxy));
    cv::Matx<double, 2, kShapes> coupling;
    cv::Matx<double, kShapes, kShapes> shapeBlock;
    for (int i = 0; i < kShapes; ++i) {
      coupling(0, i) = h(0, 2 + i), coupling(1, i) = h(1, 2 + i);
      for (int l = 0; l < kShapes; ++l) shapeBlock(i, l) = h(2 + i, 2 + l);
    }
    pull_ = shiftInverse_ * coupling;
    information_ = shapeBlock - coupling.t() * pull_;
    for (int i = 0; i < kShapes; ++i) perSpread_[i] = spread[i] > 0 ? 1 / std::sqrt(spread[i]) : 0;
    edge_ = r_ * std::sqrt(std::abs(cv::determinant(fromPlane * startShape * toPlane)));
  }

  // The first `shapes` of the shape information, and whether the patch fixes them: per squared
  // level pixel of the samples' motion they are held to the shift's standard (a patch as round as
  // a disc does not fix its turn, nor a patch of parallel stripes its scale).
  template <int shapes>
  ShapeSystem<shapes> system() const {
    ShapeSystem<shapes> s;
    typename ShapeSystem<shapes>::Square perSpread;
    for (int i = 0; i < shapes; ++i) {
      s.pull(0, i) = pull_(0, i), s.pull(1, i) = pull_(1, i);
      for (int l = 0; l < shapes; ++l) {
        s.information(i, l) = information_(i, l);
        perSpread(i, l) = information_(i, l) * perSpread_[i] * perSpread_[l];
      }
    }
    s.fixed = eigenvaluesAtLeast<shapes>(perSpread, o_.minEigenvalue);
    s.inverse = s.fixed ? inversePositiveDefinite<shapes>(s.information) : ShapeSystem<shapes>::Square::zeros();
    return s;
  }

  // Gauss-Newton from `from`: the shift with the system's shapes estimated, or (shaping false)
  // the shift alone, from's shape held. significance: the squared Mahalanobis length, in the
  // residual's noise, of the shape's coefficients (estimated) or of the step they would take
  // (held).
  template <int shapes>
  LevelResult align(const Alignment& from, const ShapeSystem<shapes>& s, bool shaping, double& significance) {
    LevelResult out;
    // h^-1 by blocks, or its shift block alone with the shape held.
    const cv::Matx22d shiftBlock = shaping ? shiftInverse_ + s.pull * s.inverse * s.pull.t() : shiftInverse_;
    const cv::Matx<double, 2, shapes> cross = -s.pull * s.inverse;
    ParameterMatrix inverse = ParameterMatrix::zeros();
    for (int i = 0; i < 2; ++i)
      for (int l = 0; l < 2; ++l) inverse(i, l) = shiftBlock(i, l);
    if (shaping)
      for (int i = 0; i < shapes; ++i) {
        inverse(0, 2 + i) = inverse(2 + i, 0) = cross(0, i);
        inverse(1, 2 + i) = inverse(2 + i, 1) = cross(1, i);
        for (int l = 0; l < shapes; ++l) inverse(2 + i, 2 + l) = s.inverse(i, l);
      }
    const int count = static_cast<int>(templ_.size());
    cv::Point2d shift(from.shift.x / gb_.step.x, from.shift.y / gb_.step.y);  // level pixels of b
    cv::Matx22d shape = from.shape;
    double residual = 0;
    ParameterVector b;
    for (int iteration = 0; iteration < o_.maxIterations; ++iteration) {
      if (!sample(shift, shape, out.outcome)) return out;
      b = ParameterVector::all(0);
      residual = 0;
      for (int k = 0; k < count; ++k) {
        const double e = sample_[k] - templ_[k];
        for (int i = 0; i < columns_; ++i) b[i] += jacobian_[k][i] * e;
        residual += e * e;
      }
      const ParameterVector delta = inverse * b;
      // The warp composed with the increment's inverse: shaped back on the plane, then shifted
      // back along b's level axes as the warp now maps them.
      cv::Matx22d increment = cv::Matx22d::eye();
      for (int i = 0; i < shapes; ++i) increment += delta[2 + i] * kGenerators[i];
      shape = shape * increment.inv();
      const cv::Vec2d back = fromPlane_ * shape * back_ * cv::Vec2d(delta[0], delta[1]);
      shift -= cv::Point2d(back[0], back[1]);
      // Diverged: too far, or a patch scaled by more than twice the keypoints' size ratio, or
      // mirrored.
      const cv::Vec2d scales = singularValues(shape);
      if (!(std::hypot(shift.x * gb_.step.x, shift.y * gb_.step.y) <= maxShift_) || !(scales[0] <= kMaxScale) ||
          !(scales[1] >= 1 / kMaxScale) || !(cv::determinant(shape) > 0))
        return out;
      double shapeStep = 0;
      for (int i = 0; i < shapes; ++i) shapeStep = std::max(shapeStep, std::abs(delta[2 + i]));
      // A shape's step settles when it moves the patch's edge as little as a shift's step must
      // move its centre.
      if (std::hypot(back[0], back[1]) < 0.01 && shapeStep * edge_ < 0.01) {
        out.outcome = LevelOutcome::Aligned;
        break;
      }
    }
    if (out.outcome != LevelOutcome::Aligned) return out;  // did not settle
    out.alignment = {{shift.x * gb_.step.x, shift.y * gb_.step.y}, shape};
    // The residual's variance per sample through the largest eigenvalue of the shift's covariance
    // (with the shape estimated, its uncertainty included).
    const double variance = residual / std::max(1, count - (shaping ? 2 + shapes : 2));
    const double cxx = shiftBlock(0, 0), cxy = shiftBlock(0, 1), cyy = shiftBlock(1, 1);
    const double largest = 0.5 * (cxx + cyy + std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy));
    out.sigmaLevel = std::sqrt(variance * largest);
    cv::Vec<double, shapes> step;
    if (shaping) {
      const cv::Matx22d away = shape - cv::Matx22d::eye();
      for (int i = 0; i < shapes; ++i) step[i] = 0.5 * away.dot(kGenerators[i]);
    } else {
      cv::Vec<double, shapes> shapeB;
      for (int i = 0; i < shapes; ++i) shapeB[i] = b[2 + i];
      step = s.inverse * (shapeB - s.pull.t() * cv::Vec2d(b[0], b[1]));
    }
    significance = variance > 0 ? step.dot(s.information * step) / variance : 0;
    return out;
  }

 private:
  // b's patch at `shift` (level pixels) and `shape`, normalised; false with the outcome set when
  // it leaves the level or has no variance.
  bool sample(const cv::Point2d& shift, const cv::Matx22d& shape, LevelOutcome& outcome) {
    const cv::Matx22d warp = fromPlane_ * shape * toPlane_;
    const cv::Point2d centre = cb_ + shift;
    // The warp is affine: its corners bound the patch. Inside the level by a pixel and more (half
    // a pixel more for the samples' rounding), every sample's neighbours are in it, and no sample
    // is checked.
    const cv::Vec2d halfU = warp * cv::Vec2d(r_, 0), halfV = warp * cv::Vec2d(0, r_);
    const double reachX = std::abs(halfU[0]) + std::abs(halfV[0]) + 0.5,
                 reachY = std::abs(halfU[1]) + std::abs(halfV[1]) + 0.5;
    if (centre.x - reachX >= 1 && centre.y - reachY >= 1 && centre.x + reachX < b_.cols - 2 &&
        centre.y + reachY < b_.rows - 2) {
      for (int v = -r_, k = 0; v <= r_; ++v)
        for (int u = -r_; u <= r_; ++u, ++k) {
          const cv::Vec2d offset = warp * cv::Vec2d(u, v);
          sample_[k] = cubic<true>(b_, centre.x + offset[0], centre.y + offset[1]);
        }
    } else {
      for (int v = -r_, k = 0; v <= r_; ++v)
        for (int u = -r_; u <= r_; ++u, ++k) {
          const cv::Vec2d offset = warp * cv::Vec2d(u, v);
          const cv::Point2d p(centre.x + offset[0], centre.y + offset[1]);
          if (!inside(b_, p, 0.0)) {
            outcome = LevelOutcome::OutsideImage;
            return false;
          }
          sample_[k] = cubic<false>(b_, p.x, p.y);
        }
    }
    float deviation = 0;
    if (!normalise(sample_, deviation)) {
      outcome = LevelOutcome::Aperture;
      return false;
    }
    return true;
  }

  const Level& b_;
  cv::Point2d cb_;
  const std::vector<float>& templ_;
  const std::vector<ParameterVector>& jacobian_;
  int columns_;  // the Jacobian's columns computed: the shift's alone, or every parameter's
  cv::Matx22d toPlane_, fromPlane_;
  cv::Matx22d back_;  // b's level pixels at the start to plane units before the start's shape
  LevelGrid gb_;
  int r_;
  double maxShift_;
  const MatchRefinementOptions& o_;
  std::vector<float> sample_;
  cv::Matx22d shiftInverse_;
  cv::Matx<double, 2, kShapes> pull_;
  cv::Matx<double, kShapes, kShapes> information_;
  double perSpread_[kShapes];
  double edge_;  // the patch's half side in b's level pixels
};

// Aligns b's patch on level lb with a's on level la, from `start`; a shift beyond `maxShift`
// input pixels diverged. aToPlane: a's input pixels to plane units; planeToB: plane units to b's
// input pixels (the size ratio included). Without estimateShape, start's shape is held.
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
  // b's sample of a's level pixel offset x: cb + shift + fromPlane shape toPlane x.
  const cv::Matx22d toPlane = aToPlane * cv::Matx22d(ga.step.x, 0, 0, ga.step.y);
  const cv::Matx22d fromPlane = cv::Matx22d(1 / gb.step.x, 0, 0, 1 / gb.step.y) * planeToB;
  // Inverse compositional: the increment shifts and shapes a's patch on the plane, so its
  // Jacobian is the template's gradient times the increment's motion of each sample, the same at
  // every iteration; each iteration samples b's patch only. The shift is counted in b's level
  // pixels at the start (the start warp's inverse transpose carries a's gradient there); each
  // shape moves a's offset x by its generator carried into a's level pixels.
  const cv::Matx22d carry = (fromPlane * start.shape * toPlane).inv().t();
  const cv::Matx22d intoA = toPlane.inv();
  cv::Matx22d generators[kShapes];
  for (int i = 0; i < kShapes; ++i) generators[i] = intoA * kGenerators[i] * toPlane;
  // The shapes' columns only where they are estimated: the finer levels hold the shape.
  const int columns = estimateShape ? kParameters : 2;
  std::vector<ParameterVector> jacobian(count, ParameterVector::all(0));
  // The squared level pixels a unit of each shape moves the samples by, summed.
  double spread[kShapes] = {};
  for (int v = -r, k = 0; v <= r; ++v)
    for (int u = -r; u <= r; ++u, ++k) {
      const cv::Vec2d g(gx[k] / deviation, gy[k] / deviation), x(u, v);
      const cv::Vec2d gShift = carry * g;
      jacobian[k][0] = gShift[0], jacobian[k][1] = gShift[1];
      for (int i = 0; i < columns - 2; ++i) {
        const cv::Vec2d motion = generators[i] * x;
        jacobian[k][2 + i] = g.dot(motion);
        spread[i] += motion.dot(motion);
      }
    }
  normalisedDerivative(jacobian, templ, columns);
  // The upper triangle, then mirrored.
  ParameterMatrix h = ParameterMatrix::zeros();
  for (const ParameterVector& j : jacobian)
    for (int i = 0; i < columns; ++i)
      for (int l = i; l < columns; ++l) h(i, l) += j[i] * j[l];
  for (int i = 0; i < columns; ++i)
    for (int l = 0; l < i; ++l) h(i, l) = h(l, i);
  const double hxx = h(0, 0), hxy = h(0, 1), hyy = h(1, 1), det = hxx * hyy - hxy * hxy;
  if (!(smallerEigenvalue({hxx, hxy, hxy, hyy}) / count >= o.minEigenvalue) || !(det > 0)) {
    result.outcome = LevelOutcome::Aperture;
    return result;
  }
  LevelAlignment level(ib, cb, templ, jacobian, h, spread, toPlane, fromPlane, start.shape, gb, r, maxShift, o,
                       columns);
  double significance = 0;
  if (!estimateShape) return level.align(start, ShapeSystem<2>{}, false, significance);
  const double threshold = kShapeSignificance * kShapeSignificance;
  const ShapeSystem<2> similar = level.system<2>();
  if (!similar.fixed) return level.align(start, similar, false, significance);
  // Estimating a shape costs the shift precision wherever it moves the same samples (the tests'
  // rendered plane, which did not roll: median error 0.068 -> 0.072 px with the turn), so a shape
  // is kept only where it stands out of its noise: all four, else turn and scale, else the shift
  // alone, the patch unturned at the keypoints' size ratio, from where the turn and scale put it.
  // Where that one does not settle, the shift alone stands if it sees no turn or scale either.
  const ShapeSystem<4> every = level.system<4>();
  if (every.fixed) {
    const LevelResult slanted = level.align(start, every, true, significance);
    if (slanted.outcome == LevelOutcome::Aligned && significance > threshold) return slanted;
  }
  const LevelResult shaped = level.align(start, similar, true, significance);
  if (shaped.outcome == LevelOutcome::Aligned && significance > threshold) return shaped;
  const Alignment plain{shaped.outcome == LevelOutcome::Aligned ? shaped.alignment.shift : start.shift,
                        cv::Matx22d::eye()};
  const LevelResult held = level.align(plain, similar, false, significance);
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
    if (std::abs(difference) > kOrientationNoiseDeg) alignment.shape = rotation(difference * CV_PI / 180.0);
  }
  // The keypoints' own levels, then the finest that the options and both pyramids allow, from the
  // first result. Through every level between, the stereo benchmark's figures were the same (to
  // 0.001 px) at 1.4 times the time.
  const int finest = std::min({o.finerLevels, ka.octave, kb.octave});
  const double ownStep = pb.grid(kb.octave).step.x;
  double sigmaLevel = 0;
  int level = -1;
  for (int j = 0;; j = finest) {
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
    if (j == finest) break;
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
