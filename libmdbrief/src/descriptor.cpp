#include "mdbrief/descriptor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "mdbrief/patterns.hpp"
#include "mdbrief/tangent_plane.hpp"

namespace mdbrief {
namespace {

// Sample positions are quantised to 1/32 pixel (cv::remap's INTER_BITS) and interpolated with
// integer weights: every form that computes the same position within 1e-9 px gets the same
// bits, which makes dBRIEF with a distortion-free pinhole equal BRIEF bit for bit.
constexpr int kSubBits = 5;
constexpr int kSub = 1 << kSubBits;

struct FixedPoint {
  int x, y;
};

// Level coordinates beyond +-2^20 px are outside any image; refusing them keeps the
// fixed-point conversion far from int overflow.
inline bool quantise(double x, double y, FixedPoint& p) {
  constexpr double kLimit = 1 << 20;
  if (!(std::abs(x) < kLimit && std::abs(y) < kLimit)) return false;
  p = {static_cast<int>(std::floor(x * kSub + 0.5)), static_cast<int>(std::floor(y * kSub + 0.5))};
  return true;
}

// Bilinear reads pixel x0 + 1, which must be <= width - 1; nearest reads a subset of those.
bool allInside(const FixedPoint* pts, int count, int width, int height) {
  int minX = 0, minY = 0, maxX = 0, maxY = 0;
  if (count > 0) minX = maxX = pts[0].x, minY = maxY = pts[0].y;
  for (int i = 1; i < count; ++i) {
    minX = std::min(minX, pts[i].x), maxX = std::max(maxX, pts[i].x);
    minY = std::min(minY, pts[i].y), maxY = std::max(maxY, pts[i].y);
  }
  return minX >= 0 && minY >= 0 && maxX < (width - 1) * kSub && maxY < (height - 1) * kSub;
}

inline int sampleBilinear(const cv::Mat& img, const FixedPoint& p) {
  const int x0 = p.x >> kSubBits, y0 = p.y >> kSubBits;
  const int fx = p.x & (kSub - 1), fy = p.y & (kSub - 1);
  const uchar* r0 = img.ptr<uchar>(y0) + x0;
  const uchar* r1 = r0 + img.step[0];
  return (r0[0] * (kSub - fx) + r0[1] * fx) * (kSub - fy) + (r1[0] * (kSub - fx) + r1[1] * fx) * fy;
}

inline int sampleNearest(const cv::Mat& img, const FixedPoint& p) {
  return img.ptr<uchar>((p.y + kSub / 2) >> kSubBits)[(p.x + kSub / 2) >> kSubBits];
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

// Fills pts (2 per test) with quantised level coordinates. False if a point cannot be
// projected.
bool placeTests(const Placement& pl, const Camera* camera, const std::vector<TestPair>& tests,
                FixedPoint* pts) {
  const int n = static_cast<int>(tests.size());
  const auto& m = pl.map;
  for (int d = 0; d < n; ++d) {
    const TestPair& t = tests[d];
    const int qs[2][2] = {{t.x1, t.y1}, {t.x2, t.y2}};
    for (int k = 0; k < 2; ++k) {
      const double qx = qs[k][0], qy = qs[k][1];
      double x, y;
      if (pl.affine) {
        x = pl.centre.x + m(0, 0) * qx + m(0, 1) * qy;
        y = pl.centre.y + m(1, 0) * qx + m(1, 1) * qy;
      } else {
        const cv::Point2d plane(pl.frame->anchor.x + m(0, 0) * qx + m(0, 1) * qy,
                                pl.frame->anchor.y + m(1, 0) * qx + m(1, 1) * qy);
        cv::Point2d px;
        if (!planeToPixel(*camera, pl.frame->lambda, plane, px)) return false;
        x = px.x / pl.scale;
        y = px.y / pl.scale;
      }
      if (!quantise(x, y, pts[2 * d + k])) return false;
    }
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

template <int (*Sample)(const cv::Mat&, const FixedPoint&)>
void packBits(const cv::Mat& img, const FixedPoint* pts, int nTests, uchar* out) {
  for (int byte = 0; byte < nTests / 8; ++byte) {
    unsigned v = 0;
    for (int b = 0; b < 8; ++b) {
      const int d = byte * 8 + b;
      v |= static_cast<unsigned>(Sample(img, pts[2 * d]) < Sample(img, pts[2 * d + 1])) << b;
    }
    out[byte] = static_cast<uchar>(v);
  }
}

void sampleDescriptor(const cv::Mat& img, const FixedPoint* pts, int nTests, Sampling sampling,
                      uchar* out) {
  if (sampling == Sampling::Bilinear)
    packBits<sampleBilinear>(img, pts, nTests, out);
  else
    packBits<sampleNearest>(img, pts, nTests, out);
}

}  // namespace

void validate(const DescriptorOptions& o) {
  if (o.bits < 32 || o.bits > 512 || o.bits % 32 != 0)
    throw std::invalid_argument("descriptor option bits=" + std::to_string(o.bits) +
                                ": must be 32..512 in steps of 32");
  if (!(o.maskRotationDeg > 0.0 && o.maskRotationDeg < 90.0))
    throw std::invalid_argument("descriptor option maskRotationDeg must be in (0, 90)");
  if (!(o.maxIncidenceDeg > 0.0 && o.maxIncidenceDeg < 90.0))
    throw std::invalid_argument("descriptor option maxIncidenceDeg must be in (0, 90)");
  if (o.pyramid.levels < 1 || !(o.pyramid.scaleFactor > 1.0))
    throw std::invalid_argument("descriptor pyramid options: levels >= 1 and scaleFactor > 1 required");
}

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options)
    : DescriptorExtractor(camera, options,
                          resolveTestSet(options.pattern.empty() ? defaultTestSetName() : options.pattern)) {}

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options, const TestSet& tests)
    : camera_(std::move(camera)), options_(std::move(options)) {
  validate(options_);
  if (!camera_ && options_.kind != DescriptorKind::Brief)
    throw std::invalid_argument("dBRIEF and mdBRIEF need a camera model");
  if (static_cast<int>(tests.tests.size()) < options_.bits)
    throw std::invalid_argument("test set '" + tests.name + "' has " + std::to_string(tests.tests.size()) +
                                " tests, fewer than bits=" + std::to_string(options_.bits));
  tests_ = tests.first(options_.bits);
}

namespace {

// Placements of the test set for one keypoint: rotation 0, then (mdBRIEF) +delta and -delta.
// Returns the number of placements, 0 when the keypoint cannot be described.
int placementsFor(const DescriptorOptions& o, const Camera* camera, const cv::KeyPoint& kp, double scale,
                  TangentPlaneFrame& frame, std::array<Placement, 3>& out) {
  if (!std::isfinite(kp.pt.x) || !std::isfinite(kp.pt.y)) return 0;
  const int count = o.kind == DescriptorKind::MdBrief ? 3 : 1;
  const double deltas[3] = {0.0, o.maskRotationDeg, -o.maskRotationDeg};
  const bool oriented = o.useOrientation && kp.angle >= 0.f;

  if (o.kind == DescriptorKind::Brief) {
    for (int r = 0; r < count; ++r) {
      out[r].centre = cv::Point2d(kp.pt.x / scale, kp.pt.y / scale);
      out[r].map = rotation((oriented ? kp.angle : 0.0) + deltas[r]);
      out[r].scale = scale;
    }
    return count;
  }

  const auto f = tangentPlaneAt(*camera, cv::Point2d(kp.pt.x, kp.pt.y), o.maxIncidenceDeg);
  if (!f) return 0;
  frame = *f;
  const double planeAngle = oriented ? imageAngleToPlaneAngle(frame.jacobian, kp.angle) : 0.0;
  for (int r = 0; r < count; ++r) {
    const cv::Matx22d rot = rotation(planeAngle + deltas[r]);
    Placement& pl = out[r];
    pl.scale = scale;
    if (o.form == DistortionForm::Affine) {
      // Shape from the camera, size from the detector: unit-determinant Jacobian.
      const double det = std::abs(cv::determinant(frame.jacobian));
      pl.affine = true;
      pl.centre = cv::Point2d(kp.pt.x / scale, kp.pt.y / scale);
      pl.map = frame.jacobian * (1.0 / std::sqrt(det)) * rot;
    } else {
      pl.affine = false;
      pl.frame = &frame;
      pl.map = rot * scale;
    }
  }
  return count;
}

}  // namespace

void DescriptorExtractor::compute(const ImagePyramid& pyramid, std::vector<cv::KeyPoint>& keypoints,
                                  cv::Mat& descriptors, cv::Mat* masks) const {
  const int n = static_cast<int>(keypoints.size());
  const int bytes = descriptorBytes();
  const int nTests = options_.bits;
  const bool wantMasks = options_.kind == DescriptorKind::MdBrief;
  int maxOctave = 0;
  for (int i = 0; i < n; ++i) {
    const int oct = keypoints[i].octave;
    if (oct < 0 || oct >= pyramid.levels())
      throw std::invalid_argument("keypoint " + std::to_string(i) + " has octave " + std::to_string(oct) +
                                  " but the pyramid has " + std::to_string(pyramid.levels()) + " levels");
    maxOctave = std::max(maxOctave, oct);
  }
  if (n > 0) pyramid.prepareSmoothed(maxOctave);

  cv::Mat desc(n, bytes, CV_8U, cv::Scalar(0)), mask(wantMasks ? n : 0, bytes, CV_8U, cv::Scalar(0));
  std::vector<uchar> ok(n, 0);
  const Camera* camera = camera_.get();

  tbb::parallel_for(tbb::blocked_range<int>(0, n, 16), [&](const tbb::blocked_range<int>& range) {
    std::vector<FixedPoint> pts(3 * 2 * nTests);
    std::array<uchar, 64> bits[3];
    TangentPlaneFrame frame;
    std::array<Placement, 3> placements;
    for (int i = range.begin(); i != range.end(); ++i) {
      const cv::KeyPoint& kp = keypoints[i];
      const cv::Mat& img = pyramid.smoothed(kp.octave);
      const int count = placementsFor(options_, camera, kp, pyramid.scale(kp.octave), frame, placements);
      bool good = count > 0;
      for (int r = 0; good && r < count; ++r) {
        FixedPoint* p = &pts[2 * nTests * r];
        good = placeTests(placements[r], camera, tests_.tests, p) && allInside(p, 2 * nTests, img.cols, img.rows) &&
               (!camera || cornersValid(placements[r], *camera));
      }
      if (!good) continue;
      for (int r = 0; r < count; ++r) sampleDescriptor(img, &pts[2 * nTests * r], nTests, options_.sampling, bits[r].data());
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
    if (kept != i) {
      keypoints[kept] = keypoints[i];
      desc.row(i).copyTo(desc.row(kept));
      if (wantMasks) mask.row(i).copyTo(mask.row(kept));
    }
    ++kept;
  }
  keypoints.resize(kept);
  descriptors = desc.rowRange(0, kept).clone();
  if (masks) {
    if (wantMasks)
      *masks = mask.rowRange(0, kept).clone();
    else
      masks->release();
  }
}

void DescriptorExtractor::compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints,
                                  cv::Mat& descriptors, cv::Mat* masks) const {
  int levels = 1;
  for (const auto& kp : keypoints) levels = std::max(levels, kp.octave + 1);
  const ImagePyramid pyramid(image, options_.pyramid, levels);
  compute(pyramid, keypoints, descriptors, masks);
}

std::vector<std::pair<cv::Point2f, cv::Point2f>> DescriptorExtractor::testPositions(
    const cv::KeyPoint& keypoint) const {
  const double scale = std::pow(options_.pyramid.scaleFactor, std::max(0, keypoint.octave));
  TangentPlaneFrame frame;
  std::array<Placement, 3> placements;
  if (placementsFor(options_, camera_.get(), keypoint, scale, frame, placements) == 0) return {};
  const int nTests = options_.bits;
  std::vector<FixedPoint> pts(2 * nTests);
  if (!placeTests(placements[0], camera_.get(), tests_.tests, pts.data())) return {};
  std::vector<std::pair<cv::Point2f, cv::Point2f>> out(nTests);
  const float f = static_cast<float>(scale) / kSub;
  for (int d = 0; d < nTests; ++d)
    out[d] = {cv::Point2f(pts[2 * d].x * f, pts[2 * d].y * f), cv::Point2f(pts[2 * d + 1].x * f, pts[2 * d + 1].y * f)};
  return out;
}

}  // namespace mdbrief
