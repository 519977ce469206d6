#include "mdbrief/descriptor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "descriptor_kernels.hpp"
#include "mdbrief/patterns.hpp"
#include "mdbrief/simd_level.hpp"
#include "mdbrief/tangent_plane.hpp"

namespace mdbrief {
namespace {

using namespace descriptor_kernels;

// Quantised sample positions of one placement, structure of arrays so placement, bounds check
// and sampling vectorise: with n tests, element d is the first point of test d, element n + d
// its second point.
struct Positions {
  int* x;
  int* y;
};

// Level coordinates beyond +-2^20 px are outside any image; refusing them keeps the
// fixed-point conversion far from int overflow.
constexpr double kCoordinateLimit = 1 << 20;

inline int sampleNearest(const uchar* data, size_t step, int px, int py) {
  return data[((py + kSub / 2) >> kSubBits) * step + ((px + kSub / 2) >> kSubBits)];
}

cv::Matx22d rotation(double deg) {
  const double a = deg * CV_PI / 180.0, c = std::cos(a), s = std::sin(a);
  return {c, -s, s, c};
}

// Where one rotation of the test set lands for one keypoint. Either an affine map of the
// offsets (BRIEF, the Affine form) or the paper's point-wise projection from Pi_lambda.
struct Placement {
  bool affine = true;
  cv::Point2d centre;        // affine: level coordinates of the keypoint
  cv::Matx22d map;           // affine: offset -> level coordinates; paper: offset -> plane
  const TangentPlaneFrame* frame = nullptr;  // paper form
  double scale = 1.0;        // octave scale (level-0 px per level px)
};

// Test offsets as doubles, laid out as Positions.
struct Offsets {
  std::vector<double> x, y;
};

void affineCoordinate(double c, double a, double b, const double* qa, const double* qb, int* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = toFixed(c + a * qa[i] + b * qb[i]);
}

// Fills p with quantised level coordinates. False if a point cannot be projected or lies
// absurdly far outside any image.
bool placeTests(const Placement& pl, const Camera* camera, const Offsets& q, const SamplingKernels& kernels,
                Positions p) {
  const int n = static_cast<int>(q.x.size());
  const auto& m = pl.map;
  if (pl.affine) {
    const double reach = (std::abs(m(0, 0)) + std::abs(m(0, 1)) + std::abs(m(1, 0)) + std::abs(m(1, 1))) * kPatchHalf;
    if (!(std::abs(pl.centre.x) + reach < kCoordinateLimit && std::abs(pl.centre.y) + reach < kCoordinateLimit))
      return false;
    kernels.affineCoordinate(pl.centre.x, m(0, 0), m(0, 1), q.x.data(), q.y.data(), p.x, n);
    kernels.affineCoordinate(pl.centre.y, m(1, 0), m(1, 1), q.x.data(), q.y.data(), p.y, n);
    return true;
  }
  for (int i = 0; i < n; ++i) {
    const cv::Point2d plane(pl.frame->anchor.x + m(0, 0) * q.x[i] + m(0, 1) * q.y[i],
                            pl.frame->anchor.y + m(1, 0) * q.x[i] + m(1, 1) * q.y[i]);
    cv::Point2d px;
    if (!planeToPixel(*camera, pl.frame->lambda, plane, px)) return false;
    const double x = px.x / pl.scale, y = px.y / pl.scale;
    if (!(std::abs(x) < kCoordinateLimit && std::abs(y) < kCoordinateLimit)) return false;
    p.x[i] = toFixed(x);
    p.y[i] = toFixed(y);
  }
  return true;
}

// The corners of the offset square, mapped like the tests, must lie in the camera's valid area.
// The valid areas of all models are convex (image rectangle intersected with an image circle),
// so for the affine placements this covers every test point.
bool cornersValid(const Placement& pl, const Camera& camera) {
  constexpr double lo = -kPatchHalf, hi = kPatchHalf - 1;
  const cv::Point2d corners[4] = {{lo, lo}, {hi, lo}, {lo, hi}, {hi, hi}};
  for (const auto& q : corners) {
    const cv::Vec2d o = pl.map * cv::Vec2d(q.x, q.y);
    cv::Point2d px;
    if (pl.affine) {
      px = (pl.centre + cv::Point2d(o[0], o[1])) * pl.scale;
    } else if (!planeToPixel(camera, pl.frame->lambda, pl.frame->anchor + cv::Point2d(o[0], o[1]), px)) {
      return false;
    }
    if (!camera.isValid(px)) return false;
  }
  return true;
}

template <int (*Sample)(const uint8_t*, size_t, int, int)>
void packBits(const uint8_t* data, size_t step, const int* x, const int* y, int nTests, uint8_t* out) {
  for (int byte = 0; byte < nTests / 8; ++byte) {
    unsigned v = 0;
    for (int b = 0; b < 8; ++b) {
      const int d = byte * 8 + b;
      v |= static_cast<unsigned>(Sample(data, step, x[d], y[d]) < Sample(data, step, x[nTests + d], y[nTests + d]))
           << b;
    }
    out[byte] = static_cast<uint8_t>(v);
  }
}

void centroidMoments(const uint8_t* data, size_t step, const int* x, const int* y, const int* u, const int* v,
                     int n, long long& m10, long long& m01) {
  m10 = m01 = 0;
  for (int i = 0; i < n; ++i) {
    const long long val = sampleBilinear(data, step, x[i], y[i]);
    m10 += val * u[i];
    m01 += val * v[i];
  }
}

}  // namespace

SamplingKernels descriptor_kernels::portableSamplingKernels() {
  return {affineCoordinate, packBits<sampleBilinear>, allInsideImage, centroidMoments};
}

namespace {

SamplingKernels activeSamplingKernels() {
#if defined(MDBRIEF_X86_KERNELS)
  if (activeSimdLevel() >= SimdLevel::Avx2) return avx2SamplingKernels();
#endif
  return portableSamplingKernels();
}

void sampleDescriptor(const cv::Mat& img, const Positions& p, int nTests, Sampling sampling,
                      const SamplingKernels& kernels, uchar* out) {
  if (sampling == Sampling::Nearest) return packBits<sampleNearest>(img.data, img.step[0], p.x, p.y, nTests, out);
  kernels.packBitsBilinear(img.data, img.step[0], p.x, p.y, nTests, out);
}

Offsets offsetsOf(const TestSet& tests) {
  const size_t n = tests.tests.size();
  Offsets q{std::vector<double>(2 * n), std::vector<double>(2 * n)};
  for (size_t d = 0; d < n; ++d) {
    const TestPair& t = tests.tests[d];
    q.x[d] = t.x1, q.y[d] = t.y1, q.x[n + d] = t.x2, q.y[n + d] = t.y2;
  }
  return q;
}

}  // namespace

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options)
    : DescriptorExtractor(camera, options,
                          resolveTestSet(options.pattern.empty() ? defaultTestSetName() : options.pattern)) {}

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options, const TestSet& tests)
    : camera_(std::move(camera)), options_(std::move(options)) {
  validate(options_);
  if (!camera_ && usesCamera(options_.kind)) throw std::invalid_argument("dBRIEF and mdBRIEF need a camera model");
  if (static_cast<int>(tests.tests.size()) < options_.bits)
    throw std::invalid_argument("test set '" + tests.name + "' has " + std::to_string(tests.tests.size()) +
                                " tests, fewer than bits=" + std::to_string(options_.bits));
  tests_ = tests.first(options_.bits);
}

namespace {

// The centroid is measured on the smoothed level (sigma 2 px), which is band-limited enough
// for every second pixel: a quarter of the samples, the same recognition in the detected
// simulation (fisheye, rolled: dBRIEF 57.0 vs 57.6 %, mdBRIEF 63.8 vs 63.4 %), covariance
// error 1.1 vs 1.0 degrees (tests/test_descriptor_pinhole.cpp).
constexpr int kDiscStep = 2;

// The disc u^2 + v^2 <= r^2 (u, v multiples of step) of the intensity centroid, padded with
// (0, 0) to a multiple of 8 samples (the padding has zero moment arms, so it adds nothing).
struct Disc {
  Offsets offsets;
  std::vector<int> u, v;
};

Disc discOf(int radius, int step) {
  Disc d;
  for (int v = -radius; v <= radius; v += step)
    for (int u = -radius; u <= radius; u += step)
      if (u * u + v * v <= radius * radius) d.u.push_back(u), d.v.push_back(v);
  while (d.u.size() % 8) d.u.push_back(0), d.v.push_back(0);
  d.offsets.x.assign(d.u.begin(), d.u.end());
  d.offsets.y.assign(d.v.begin(), d.v.end());
  return d;
}

// Intensity-centroid angle (degrees, in the offset frame) of the disc mapped by `map` around
// `centre` (level coordinates). Empty if the disc leaves the image.
std::optional<double> centroidAngle(const cv::Mat& img, const cv::Point2d& centre, const cv::Matx22d& map,
                                    const Disc& disc, const SamplingKernels& kernels, int* xs, int* ys) {
  const int n = static_cast<int>(disc.u.size());
  kernels.affineCoordinate(centre.x, map(0, 0), map(0, 1), disc.offsets.x.data(), disc.offsets.y.data(), xs, n);
  kernels.affineCoordinate(centre.y, map(1, 0), map(1, 1), disc.offsets.x.data(), disc.offsets.y.data(), ys, n);
  if (!kernels.allInside(xs, ys, n, img.cols, img.rows)) return std::nullopt;
  long long m10, m01;
  kernels.centroidMoments(img.data, img.step[0], xs, ys, disc.u.data(), disc.v.data(), n, m10, m01);
  if (m10 == 0 && m01 == 0) return 0.0;
  return std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * 180.0 / CV_PI;
}

// cv::ORB's patch size: a keypoint of this size at scale 1 is described with step 1.
constexpr double kReferenceSize = 31.0;

// Where a keypoint is sampled: the pyramid level whose scale is nearest (in log) to the
// footprint's, and the footprint relative to that level (1 when it is the level's own).
struct Support {
  int level = -1;  // -1: the size is not finite or the footprint is under one pixel
  double fraction = 1.0;
};

// The tests' 31-pixel diameter spans supportScale * size input pixels.
Support supportOf(float size, double supportScale, const std::vector<double>& scales) {
  const double s = supportScale * static_cast<double>(size) / kReferenceSize;
  // Under one pixel every test compares nearly the same interpolated value: all zeros, all
  // stable, and any two such keypoints would match at distance 0.
  if (!(s * kReferenceSize >= 1.0) || !std::isfinite(s)) return {};
  Support out;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < static_cast<int>(scales.size()); ++k)
    if (const double d = std::abs(std::log(s / scales[k])); d < best - 1e-9) best = d, out.level = k;
  out.fraction = s / scales[out.level];
  // A keypoint at its level's own size (cv::ORB: size = 31 * scale) keeps the exact integer
  // footprint it always had, whatever the float rounding of its size.
  if (std::abs(out.fraction - 1.0) < 1e-4) out.fraction = 1.0;
  return out;
}

std::vector<double> pyramidScales(const PyramidOptions& o) {
  std::vector<double> scales(o.levels);
  for (int k = 0; k < o.levels; ++k) scales[k] = std::pow(o.scaleFactor, k - o.firstLevel);
  return scales;
}

std::vector<double> pyramidScales(const ImagePyramid& pyramid) {
  std::vector<double> scales(pyramid.levels());
  for (int k = 0; k < pyramid.levels(); ++k) scales[k] = pyramid.scale(k);
  return scales;
}

// What placementsFor needs to re-measure the orientation on the tangent plane; null image =
// use the keypoint's angle.
struct OrientationInput {
  const cv::Mat* image = nullptr;
  const SamplingKernels* kernels = nullptr;
  const Disc* disc = nullptr;
  int* xs = nullptr;
  int* ys = nullptr;
};

// Placements of the test set for one keypoint sampled on the level of scale `scale`, the
// footprint enlarged by `fraction` on that level (Support). Rotation 0, then (masked kinds)
// +delta and -delta. Returns the number of placements, 0 when the keypoint cannot be described.
// imageAngle receives the image direction (degrees) of a re-measured orientation, else -1.
int placementsFor(const DescriptorOptions& o, const Camera* camera, const cv::KeyPoint& kp, double scale,
                  double fraction, const OrientationInput& measure, TangentPlaneFrame& frame,
                  std::array<Placement, 3>& out, float& imageAngle) {
  imageAngle = -1.f;
  if (!std::isfinite(kp.pt.x) || !std::isfinite(kp.pt.y)) return 0;
  const int count = hasMasks(o.kind) ? 3 : 1;
  const double deltas[3] = {0.0, o.maskRotationDeg, -o.maskRotationDeg};
  const cv::Point2d centre(kp.pt.x / scale, kp.pt.y / scale);

  if (!usesCamera(o.kind)) {
    const bool oriented = o.useOrientation && kp.angle >= 0.f;
    for (int r = 0; r < count; ++r) {
      out[r].centre = centre;
      out[r].map = rotation((oriented ? kp.angle : 0.0) + deltas[r]) * fraction;
      out[r].scale = scale;
    }
    return count;
  }

  const auto f = tangentPlaneAt(*camera, cv::Point2d(kp.pt.x, kp.pt.y), o.maxIncidenceDeg);
  if (!f) return 0;
  frame = *f;
  // Offset -> level coordinates before rotation. Affine: shape from the camera, size from the
  // detector (unit-determinant Jacobian). Paper: the Jacobian itself (plane offsets are scaled
  // by the octave scale, level coordinates divide it out); used for the orientation disc.
  const cv::Matx22d shape = (o.form == DistortionForm::Affine
                                 ? frame.jacobian * (1.0 / std::sqrt(std::abs(cv::determinant(frame.jacobian))))
                                 : frame.jacobian) *
                            fraction;
  double planeAngle = 0.0;
  if (o.useOrientation && o.orientation == OrientationSource::TangentPlane && measure.image) {
    const auto a = centroidAngle(*measure.image, centre, shape, *measure.disc, *measure.kernels, measure.xs, measure.ys);
    if (!a) return 0;
    planeAngle = *a;
    const double rad = planeAngle * CV_PI / 180.0;
    const cv::Vec2d d = shape * cv::Vec2d(std::cos(rad), std::sin(rad));
    double deg = std::atan2(d[1], d[0]) * 180.0 / CV_PI;
    if (deg < 0) deg += 360.0;
    imageAngle = deg >= 360.0 ? 0.f : static_cast<float>(deg);
  } else if (o.useOrientation && kp.angle >= 0.f) {
    planeAngle = imageAngleToPlaneAngle(frame.jacobian, kp.angle);
  }
  for (int r = 0; r < count; ++r) {
    const cv::Matx22d rot = rotation(planeAngle + deltas[r]);
    Placement& pl = out[r];
    pl.scale = scale;
    if (o.form == DistortionForm::Affine) {
      pl.affine = true;
      pl.centre = centre;
      pl.map = shape * rot;
    } else {
      pl.affine = false;
      pl.frame = &frame;
      pl.map = rot * (scale * fraction);
    }
  }
  return count;
}

// Per-thread buffers of placeChecked.
struct PlacementScratch {
  PlacementScratch(int nTests, size_t discSamples)
      : xs(3 * 2 * nTests), ys(3 * 2 * nTests), discX(discSamples), discY(discSamples) {}
  std::vector<int> xs, ys, discX, discY;  // rotation r at 2 * nTests * r
  TangentPlaneFrame frame;
  std::array<Placement, 3> placements;
};

// The one check of compute() and testPositions(): places every rotation of the tests of `kp`
// on `img` (the smoothed level of `support`) into s.xs / s.ys and returns the number of
// placements, 0 when the keypoint cannot be described (a test point that cannot be projected,
// leaves the level or, with a camera, the valid area). disc: null unless the angle is re-measured.
int placeChecked(const DescriptorOptions& o, const Camera* camera, const Offsets& offsets, const Disc* disc,
                 const SamplingKernels& kernels, const cv::KeyPoint& kp, const cv::Mat& img, double scale,
                 const Support& support, PlacementScratch& s, float& imageAngle) {
  const int nTests = o.bits;
  const OrientationInput in{disc ? &img : nullptr, &kernels, disc, s.discX.data(), s.discY.data()};
  const int count = placementsFor(o, camera, kp, scale, support.fraction, in, s.frame, s.placements, imageAngle);
  for (int r = 0; r < count; ++r) {
    const Positions p{&s.xs[2 * nTests * r], &s.ys[2 * nTests * r]};
    if (!placeTests(s.placements[r], camera, offsets, kernels, p) ||
        !kernels.allInside(p.x, p.y, 2 * nTests, img.cols, img.rows) ||
        (camera && !cornersValid(s.placements[r], *camera)))
      return 0;
  }
  return count;
}

}  // namespace

bool DescriptorExtractor::measuresOrientation() const {
  return usesCamera(options_.kind) && options_.useOrientation && options_.orientation == OrientationSource::TangentPlane;
}

void DescriptorExtractor::compute(const ImagePyramid& pyramid, std::vector<cv::KeyPoint>& keypoints,
                                  cv::OutputArray descriptors, cv::OutputArray masks) const {
  const int n = static_cast<int>(keypoints.size());
  const int bytes = descriptorBytes();
  const int nTests = options_.bits;
  const bool wantMasks = hasMasks(options_.kind);
  // Each keypoint's level and footprint from its size; octave is not read.
  std::vector<Support> supports(n);
  int maxLevel = -1;
  for (int i = 0; i < n; ++i) {
    supports[i] = supportOf(keypoints[i].size, options_.supportScale, pyramidScales(pyramid));
    maxLevel = std::max(maxLevel, supports[i].level);
  }
  if (maxLevel >= 0) pyramid.prepareSmoothed(maxLevel);

  cv::Mat desc(n, bytes, CV_8U, cv::Scalar(0)), mask(wantMasks ? n : 0, bytes, CV_8U, cv::Scalar(0));
  std::vector<uchar> ok(n, 0);
  std::vector<float> angles(n, -1.f);
  const Camera* camera = camera_.get();
  const Offsets offsets = offsetsOf(tests_);
  const bool measure = measuresOrientation();
  const Disc disc = measure ? discOf(options_.orientationRadius, kDiscStep) : Disc{};
  const SamplingKernels kernels = activeSamplingKernels();

  tbb::parallel_for(tbb::blocked_range<int>(0, n, 16), [&](const tbb::blocked_range<int>& range) {
    PlacementScratch scratch(nTests, disc.u.size());
    std::array<uchar, 64> bits[3];
    for (int i = range.begin(); i != range.end(); ++i) {
      const Support& support = supports[i];
      if (support.level < 0) continue;  // no usable size
      const cv::Mat& img = pyramid.smoothed(support.level);
      const int count = placeChecked(options_, camera, offsets, measure ? &disc : nullptr, kernels, keypoints[i],
                                     img, pyramid.scale(support.level), support, scratch, angles[i]);
      if (count == 0) continue;
      for (int r = 0; r < count; ++r)
        sampleDescriptor(img, Positions{&scratch.xs[2 * nTests * r], &scratch.ys[2 * nTests * r]}, nTests,
                         options_.sampling, kernels, bits[r].data());
      std::copy_n(bits[0].data(), bytes, desc.ptr<uchar>(i));
      if (wantMasks) {
        uchar* m = mask.ptr<uchar>(i);
        for (int b = 0; b < bytes; ++b)
          m[b] = static_cast<uchar>(~((bits[0][b] ^ bits[1][b]) | (bits[0][b] ^ bits[2][b])));
      }
      ok[i] = 1;
    }
  });

  // Drop the keypoints that could not be described, keeping rows aligned with keypoints.
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (!ok[i]) continue;
    if (measure) keypoints[i].angle = angles[i];
    if (kept != i) {
      keypoints[kept] = keypoints[i];
      desc.row(i).copyTo(desc.row(kept));
      if (wantMasks) mask.row(i).copyTo(mask.row(kept));
    }
    ++kept;
  }
  keypoints.resize(kept);
  if (descriptors.needed()) descriptors.assign(desc.rowRange(0, kept).clone());
  if (masks.needed()) {
    if (wantMasks)
      masks.assign(mask.rowRange(0, kept).clone());
    else
      masks.release();
  }
}

void DescriptorExtractor::compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints,
                                  cv::OutputArray descriptors, cv::OutputArray masks,
                                  const PyramidOptions& pyramidOptions) const {
  const ImagePyramid pyramid(image, pyramidOptions, levelsFor(keypoints, pyramidOptions));
  compute(pyramid, keypoints, descriptors, masks);
}

int DescriptorExtractor::levelsFor(const std::vector<cv::KeyPoint>& keypoints, const PyramidOptions& pyramid) const {
  validate(pyramid);  // pyramidScales() needs at least one level
  int levels = 1;
  const std::vector<double> scales = pyramidScales(pyramid);
  for (const auto& kp : keypoints) levels = std::max(levels, supportOf(kp.size, options_.supportScale, scales).level + 1);
  return levels;
}

std::vector<std::pair<cv::Point2f, cv::Point2f>> DescriptorExtractor::testPositions(
    const ImagePyramid& pyramid, const cv::KeyPoint& keypoint) const {
  const Support support = supportOf(keypoint.size, options_.supportScale, pyramidScales(pyramid));
  if (support.level < 0) return {};
  const bool measure = measuresOrientation();
  const Disc disc = measure ? discOf(options_.orientationRadius, kDiscStep) : Disc{};
  const double scale = pyramid.scale(support.level);
  const int nTests = options_.bits;
  PlacementScratch scratch(nTests, disc.u.size());
  float imageAngle;
  if (placeChecked(options_, camera_.get(), offsetsOf(tests_), measure ? &disc : nullptr, activeSamplingKernels(),
                   keypoint, pyramid.smoothed(support.level), scale, support, scratch, imageAngle) == 0)
    return {};
  std::vector<std::pair<cv::Point2f, cv::Point2f>> out(nTests);
  const float f = static_cast<float>(scale) / kSub;
  for (int d = 0; d < nTests; ++d)
    out[d] = {cv::Point2f(scratch.xs[d] * f, scratch.ys[d] * f),
              cv::Point2f(scratch.xs[nTests + d] * f, scratch.ys[nTests + d] * f)};
  return out;
}

}  // namespace mdbrief
