#include "describe/comparison_placement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "mdbrief/internal/describe/patch_sampling.hpp"
#include "mdbrief/camera/tangent_plane.hpp"
#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief::placement {
namespace {

using namespace descriptor_kernels;

// Level coordinates beyond +-2^20 px are outside any image; refusing them keeps the
// fixed-point conversion far from int overflow.
constexpr double kCoordinateLimit = 1 << 20;

cv::Matx22d rotation(double deg) {
  const double a = deg * CV_PI / 180.0, c = std::cos(a), s = std::sin(a);
  return {c, -s, s, c};
}

// Where one rotation of the offsets lands for one keypoint. Either an affine map of the
// offsets (BRIEF, the Affine form) or the paper's point-wise projection from its plane.
struct Placement {
  bool affine = true;
  cv::Point2d centre;        // affine: level coordinates of the keypoint
  cv::Matx22d map;           // affine: offset -> level coordinates; paper: offset -> plane
  const TangentPlaneFrame* frame = nullptr;  // paper form
  LevelGrid grid;            // the level's place in the input
};

// Whether every offset, placed affinely, can be sampled in a width x height level: the corners
// of the offsets' box decide when they are inside, the points themselves otherwise.
bool affineInside(const Placement& pl, const Offsets& q, const SamplingKernels& kernels, const int* x, const int* y,
                  int width, int height) {
  const auto& m = pl.map;
  int cx[4], cy[4];
  kernels.affinePoints(pl.centre.x, pl.centre.y, m(0, 0), m(0, 1), m(1, 0), m(1, 1), q.boxX.data(), q.boxY.data(), 4,
                       cx, cy);
  return kernels.allInside(cx, cy, 4, width, height) ||
         kernels.allInside(x, y, static_cast<int>(q.x.size()), width, height);
}

// Fills x, y with quantised level coordinates. False if a point cannot be projected or lies
// absurdly far outside any image.
bool placeOffsets(const Placement& pl, const Camera* camera, const Offsets& q, const SamplingKernels& kernels,
                  int* x, int* y) {
  const int n = static_cast<int>(q.x.size());
  const auto& m = pl.map;
  if (pl.affine) {
    const double reach = (std::abs(m(0, 0)) + std::abs(m(0, 1)) + std::abs(m(1, 0)) + std::abs(m(1, 1))) * kPatchHalf;
    if (!(std::abs(pl.centre.x) + reach < kCoordinateLimit && std::abs(pl.centre.y) + reach < kCoordinateLimit))
      return false;
    kernels.affinePoints(pl.centre.x, pl.centre.y, m(0, 0), m(0, 1), m(1, 0), m(1, 1), q.x.data(), q.y.data(), n, x, y);
    return true;
  }
  for (int i = 0; i < n; ++i) {
    const cv::Point2d offset(m(0, 0) * q.x[i] + m(0, 1) * q.y[i], m(1, 0) * q.x[i] + m(1, 1) * q.y[i]);
    cv::Point2d px;
    if (!planeToPixel(*camera, *pl.frame, offset, px)) return false;
    const cv::Point2d l = pl.grid.toLevel(px);
    if (!(std::abs(l.x) < kCoordinateLimit && std::abs(l.y) < kCoordinateLimit)) return false;
    x[i] = toFixed(l.x);
    y[i] = toFixed(l.y);
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
      px = pl.grid.toInput(pl.centre + cv::Point2d(o[0], o[1]));
    } else if (!planeToPixel(camera, *pl.frame, cv::Point2d(o[0], o[1]), px)) {
      return false;
    }
    if (!camera.isValid(px)) return false;
  }
  return true;
}

// The centroid is measured on the smoothed level (sigma 2 px), which is band-limited enough
// for every second pixel: a quarter of the samples, the same recognition in the detected
// simulation (fisheye, rolled: dBRIEF 57.0 vs 57.6 %, mdBRIEF 63.8 vs 63.4 %), covariance
// error 1.1 vs 1.0 degrees (tests/test_descriptor_pinhole.cpp).
constexpr int kDiscStep = 2;

// Intensity-centroid angle (degrees, in the offset frame) of the disc mapped by `map` around
// `centre` (level coordinates). Empty if the disc leaves the image.
std::optional<double> centroidAngle(const cv::Mat& pairs, const cv::Point2d& centre, const cv::Matx22d& map,
                                    const Disc& disc, const SamplingKernels& kernels, int* xs, int* ys) {
  const int n = static_cast<int>(disc.u.size());
  kernels.affinePoints(centre.x, centre.y, map(0, 0), map(0, 1), map(1, 0), map(1, 1), disc.offsets.x.data(),
                       disc.offsets.y.data(), n, xs, ys);
  if (!kernels.allInside(xs, ys, n, pairs.cols, pairs.rows)) return std::nullopt;
  long long m10, m01;
  kernels.centroidMoments(pairs.data, pairs.step[0], xs, ys, disc.u.data(), disc.v.data(), n, m10, m01);
  if (m10 == 0 && m01 == 0) return 0.0;
  return std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * 180.0 / CV_PI;
}

// What placementsFor needs to re-measure the orientation on the tangent plane; null pairs =
// use the keypoint's angle.
struct OrientationInput {
  const cv::Mat* pairs = nullptr;  // the level's row pairs (ImagePyramid::smoothedPairs)
  const SamplingKernels* kernels = nullptr;
  const Disc* disc = nullptr;
  int* xs = nullptr;
  int* ys = nullptr;
};

// Placements of the offsets for one keypoint sampled on the level `grid` places, the
// footprint enlarged by `fraction` on that level (Support). Rotation 0, then (masked kinds)
// +delta and -delta. Returns the number of placements, 0 when the keypoint cannot be described.
// imageAngle receives the image direction (degrees) of a re-measured orientation, else -1.
int placementsFor(const DescriptorOptions& o, const Camera* camera, const cv::KeyPoint& kp, const LevelGrid& grid,
                  double fraction, const OrientationInput& measure, TangentPlaneFrame& frame,
                  std::array<Placement, 3>& out, float& imageAngle) {
  imageAngle = -1.f;
  if (!std::isfinite(kp.pt.x) || !std::isfinite(kp.pt.y)) return 0;
  // A NaN angle is no direction, as an infinite one (whose rotation fails below); without this it
  // failed `angle >= 0` and was described unrotated, as OpenCV's -1 ("none") is.
  const bool remeasured = usesCamera(o.kind) && o.orientation == OrientationSource::TangentPlane && measure.pairs;
  if (o.useOrientation && !remeasured && std::isnan(kp.angle)) return 0;
  const int count = hasMasks(o.kind) ? 3 : 1;
  const double deltas[3] = {0.0, o.maskRotationDeg, -o.maskRotationDeg};
  const cv::Point2d centre = grid.toLevel(cv::Point2d(kp.pt.x, kp.pt.y));

  if (!usesCamera(o.kind)) {
    const bool oriented = o.useOrientation && kp.angle >= 0.f;
    for (int r = 0; r < count; ++r) {
      out[r].centre = centre;
      out[r].map = grid.fromNominal() * rotation((oriented ? kp.angle : 0.0) + deltas[r]) * fraction;
      out[r].grid = grid;
    }
    return count;
  }

  const auto f =
      tangentPlaneAt(*camera, cv::Point2d(kp.pt.x, kp.pt.y), o.maxIncidenceDeg, o.form == DistortionForm::Affine);
  if (!f) return 0;
  frame = *f;
  // Offset -> level coordinates before rotation. Affine: shape from the camera, size from the
  // detector (unit-determinant Jacobian). Paper: the Jacobian itself (plane offsets are scaled
  // by the octave scale, level coordinates divide it out); used for the orientation disc.
  const cv::Matx22d shape = grid.fromNominal() *
                            (o.form == DistortionForm::Affine
                                 ? frame.jacobian * (1.0 / std::sqrt(std::abs(cv::determinant(frame.jacobian))))
                                 : frame.jacobian) *
                            fraction;
  double planeAngle = 0.0;
  if (o.useOrientation && o.orientation == OrientationSource::TangentPlane && measure.pairs) {
    const auto a = centroidAngle(*measure.pairs, centre, shape, *measure.disc, *measure.kernels, measure.xs, measure.ys);
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
    pl.grid = grid;
    if (o.form == DistortionForm::Affine) {
      pl.affine = true;
      pl.centre = centre;
      pl.map = shape * rot;
    } else {
      pl.affine = false;
      pl.frame = &frame;
      pl.map = rot * (grid.scale * fraction);
    }
  }
  return count;
}

}  // namespace

Offsets::Offsets(std::vector<int32_t> xs, std::vector<int32_t> ys) : x(std::move(xs)), y(std::move(ys)) {
  const auto beyond = [](int32_t v) { return v < -kMaxOffset || v > kMaxOffset; };
  if (std::any_of(x.begin(), x.end(), beyond) || std::any_of(y.begin(), y.end(), beyond))
    throw std::invalid_argument("Offsets: an offset lies beyond +-" + std::to_string(kMaxOffset));
  if (x.empty()) return;
  const auto [x0, x1] = std::minmax_element(x.begin(), x.end());
  const auto [y0, y1] = std::minmax_element(y.begin(), y.end());
  boxX = {*x0, *x1, *x0, *x1};
  boxY = {*y0, *y0, *y1, *y1};
}

Support supportOf(float size, double supportScale, const std::vector<double>& scales) {
  const double s = supportScale * static_cast<double>(size) / internal::kReferenceKeypointSize;
  // Under one pixel every test compares nearly the same interpolated value: all zeros, all
  // stable, and any two such keypoints would match at distance 0.
  if (!(s * internal::kReferenceKeypointSize >= 1.0) || !std::isfinite(s)) return {};
  // The level whose scale is nearest to s in log terms. Scales ascend (scaleFactor > 1), so it
  // is the first whose geometric midpoint with the next is at or above s: no logarithm per level.
  Support out;
  out.level = 0;
  for (const int last = static_cast<int>(scales.size()) - 1;
       out.level < last && s * s > scales[out.level] * scales[out.level + 1];)
    ++out.level;
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

bool measuresOrientation(const DescriptorOptions& o) {
  return usesCamera(o.kind) && o.useOrientation && o.orientation == OrientationSource::TangentPlane;
}

// The disc u^2 + v^2 <= r^2 (u, v multiples of kDiscStep), padded with (0, 0) to a multiple of
// 8 samples (the padding has zero moment arms, so it adds nothing).
Disc orientationDisc(const DescriptorOptions& o) {
  Disc d;
  if (!measuresOrientation(o)) return d;
  const int radius = o.orientationRadius;
  for (int v = -radius; v <= radius; v += kDiscStep)
    for (int u = -radius; u <= radius; u += kDiscStep)
      if (u * u + v * v <= radius * radius) d.u.push_back(u), d.v.push_back(v);
  while (d.u.size() % 8) d.u.push_back(0), d.v.push_back(0);
  d.offsets = Offsets({d.u.begin(), d.u.end()}, {d.v.begin(), d.v.end()});
  return d;
}

int placeChecked(const DescriptorOptions& o, const Camera* camera, const Offsets& offsets, const Disc& disc,
                 const SamplingKernels& kernels, const cv::KeyPoint& kp, const cv::Mat& pairs, const LevelGrid& grid,
                 const Support& support, PlacedPoints& points, float& imageAngle) {
  const int n = static_cast<int>(offsets.x.size());
  const OrientationInput in{disc.u.empty() ? nullptr : &pairs, &kernels, &disc, points.discX.data(),
                            points.discY.data()};
  TangentPlaneFrame frame;
  std::array<Placement, 3> placements;
  const int count = placementsFor(o, camera, kp, grid, support.fraction, in, frame, placements, imageAngle);
  for (int r = 0; r < count; ++r) {
    int* x = &points.x[static_cast<size_t>(n) * r];
    int* y = &points.y[static_cast<size_t>(n) * r];
    const Placement& pl = placements[r];
    if (!placeOffsets(pl, camera, offsets, kernels, x, y) ||
        !(pl.affine ? affineInside(pl, offsets, kernels, x, y, pairs.cols, pairs.rows)
                    : kernels.allInside(x, y, n, pairs.cols, pairs.rows)) ||
        (camera && !cornersValid(pl, *camera)))
      return 0;
  }
  return count;
}

}  // namespace mdbrief::placement
