// Behaviour of each camera model built from parameters (no files): round trips, closed-form
// special cases, validity limits, resized() and parameter validation.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "mdbrief/camera/double_sphere.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/ocam.hpp"
#include "mdbrief/camera/omni.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/radial.hpp"
#include "mdbrief/camera/radtan.hpp"
#include "mdbrief/camera/unified.hpp"
#include "test_camera_utils.hpp"

namespace {

using namespace mdbrief;
using mdbrief::testing::bearingRoundTrip;
using mdbrief::testing::pixelRoundTrip;

const CameraIntrinsics kPinhole{754, 480, 377.75, 377.75, 379.98, 242.82};
const CameraIntrinsics kFisheye{752, 480, 461.6, 460.3, 366.3, 249.1};

struct NamedCamera {
  std::string name;
  std::shared_ptr<Camera> camera;
};

// Round trips (pixel -> bearing -> pixel and back) agree to rounding: measured at most 5.1e-13 px
// (UCM with alpha > 1) for the closed forms and 7.6e-11 px for the iterated inverses
// (radial-tangential rational 7.6e-11, Kannala-Brandt folding 3.5e-11). 1e-9 leaves a margin of 13x.
constexpr double kRoundTripTolerancePx = 1e-9;

OcamParams lafidaParams() {
  OcamParams p;
  p.width = 754;
  p.height = 480;
  p.forward = {-209.200757992065, 0.0, 0.00213741670953883, -4.2203617319086e-06,
               1.77146086919594e-08};
  p.c = 0.999626131079017;
  p.d = -0.0034775192597376;
  p.e = 0.00385134991673147;
  p.u0 = 392.219508388648;
  p.v0 = 243.494438476351;
  p.validRadius = p.v0 + 22.0;
  return p;
}

// One camera per model, several parameter regimes (barrel / pincushion, alpha below and above
// 0.5, a Kannala-Brandt polynomial that turns back inside the image, tangential distortion).
std::vector<NamedCamera> allCameras() {
  std::vector<NamedCamera> c;
  c.push_back({"pinhole", std::make_shared<PinholeCamera>(kPinhole)});
  c.push_back({"radial barrel", std::make_shared<RadialCamera>(RadialParams{kPinhole, -1.0 / 64})});
  c.push_back({"radial pincushion", std::make_shared<RadialCamera>(RadialParams{kPinhole, 0.02, 100.0})});
  c.push_back({"kannala_brandt",
               std::make_shared<KannalaBrandtCamera>(
                   KannalaBrandtParams{kFisheye, -0.0125, 0.0578, -0.0850, 0.0436})});
  c.push_back({"kannala_brandt folding",
               std::make_shared<KannalaBrandtCamera>(KannalaBrandtParams{kFisheye, -0.3, 0, 0, 0})});
  c.push_back({"double_sphere alpha>0.5",
               std::make_shared<DoubleSphereCamera>(DoubleSphereParams{{752, 480, 348.1, 347.1, 365.8, 249.4}, -0.244, 0.566})});
  c.push_back({"double_sphere alpha<0.5",
               std::make_shared<DoubleSphereCamera>(DoubleSphereParams{{752, 480, 200, 200, 376, 240}, 0.3, 0.4})});
  c.push_back({"ucm", std::make_shared<UnifiedCamera>(UnifiedParams{kFisheye, 0.6, 1.0})});
  c.push_back({"ucm alpha>1",
               std::make_shared<UnifiedCamera>(UnifiedParams{{1920, 1080, 1313.83, 1313.27, 960.471, 546.981}, 1.01674, 1.0})});
  c.push_back({"eucm", std::make_shared<UnifiedCamera>(UnifiedParams{kFisheye, 0.586, 1.139})});
  c.push_back({"radtan",
               std::make_shared<RadTanCamera>(RadTanParams{kFisheye, -0.29, 0.08, 3e-4, -2e-5, 0.0})});
  c.push_back({"radtan folding",
               std::make_shared<RadTanCamera>(RadTanParams{kPinhole, -0.5, 0.0, 1e-3, 1e-3, 0.0})});
  RadTanParams rational{{640, 480, 269.7, 269.8, 322.6, 238.9}, 0.25, -0.02, -2.5e-4, 6e-5, 0.01};
  rational.k4 = 0.55, rational.k5 = -0.05, rational.k6 = 0.03, rational.maxRadius = 2.5;
  c.push_back({"radtan rational", std::make_shared<RadTanCamera>(rational)});
  c.push_back({"omni (Kalibr's example)",
               std::make_shared<OmniCamera>(OmniParams{{752, 480, 833.006, 830.345, 373.85, 253.749}, 0.80065662,
                                                       -0.3351875, 0.13211436, 0.00055967, 0.00057686})});
  c.push_back({"omni xi > 1", std::make_shared<OmniCamera>(OmniParams{{752, 480, 500, 500, 376, 240}, 1.5})});
  c.push_back({"ocam fitted inverse", std::make_shared<OcamCamera>(lafidaParams())});
  return c;
}

TEST(CameraModels, PixelRoundTripOverTheValidArea) {
  for (const NamedCamera& c : allCameras()) {
    const auto s = pixelRoundTrip(*c.camera, 1.5);
    SCOPED_TRACE(c.name);
    EXPECT_GT(s.valid, s.total / 4) << "too little of the image is valid";
    EXPECT_EQ(s.failed, 0);
    EXPECT_LT(s.maxError, kRoundTripTolerancePx);
    std::cout << c.name << ": pixel round trip max " << s.maxError << " px over " << s.valid
              << " pixels\n";
  }
}

TEST(CameraModels, BearingRoundTripOverTheFieldOfView) {
  for (const NamedCamera& c : allCameras()) {
    const auto s = bearingRoundTrip(*c.camera);
    SCOPED_TRACE(c.name);
    EXPECT_GT(s.valid, 1000);
    EXPECT_EQ(s.failed, 0);
    // Angular error expressed in pixels at the camera's scale.
    EXPECT_LT(s.maxError * c.camera->tangentPlaneScale(), kRoundTripTolerancePx);
  }
}

// The closed-form d pixel / d bearing against central differences of bearingToPixel, at the ray
// of every valid pixel of an 8-px grid (scaled, since bearings may have any length) and on the
// axis; the pixel and the refusals are bearingToPixel's own.
TEST(CameraModels, JacobianMatchesNumericDifferentiationOverTheImage) {
  // Large enough that OCam's Newton tolerance (1e-10 in rho) stays below the tolerance.
  constexpr double h = 1e-4;
  for (const NamedCamera& c : allCameras()) {
    SCOPED_TRACE(c.name);
    const Camera& camera = *c.camera;
    std::vector<cv::Vec3d> rays{{0.0, 0.0, 1.0}};
    const cv::Size size = camera.imageSize();
    for (double v = 0.0; v <= size.height - 1.0; v += 8.0)
      for (double u = 0.0; u <= size.width - 1.0; u += 8.0) {
        cv::Vec3d b;
        if (camera.isValid({u, v}) && camera.pixelToBearing({u, v}, b)) rays.push_back(b * 1.7);
      }
    ASSERT_GT(rays.size(), 1000u);
    int compared = 0;
    double worst = 0.0;
    for (const cv::Vec3d& b : rays) {
      cv::Point2d pixel, expected;
      cv::Matx23d j;
      const bool projected = camera.bearingToPixel(b, expected);
      ASSERT_EQ(camera.bearingToPixelJacobian(b, pixel, j), projected);
      if (!projected) continue;
      EXPECT_EQ(pixel, expected);
      cv::Matx23d numeric;
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        cv::Vec3d step(0, 0, 0);
        step[k] = h;
        cv::Point2d plus, minus;
        inside = camera.bearingToPixel(b + step, plus) && camera.bearingToPixel(b - step, minus);
        numeric(0, k) = (plus.x - minus.x) / (2 * h);
        numeric(1, k) = (plus.y - minus.y) / (2 * h);
      }
      if (!inside) continue;  // the stencil leaves the model's domain at its edge
      ++compared;
      worst = std::max(worst, cv::norm(j - numeric, cv::NORM_INF) / std::max(1.0, cv::norm(numeric, cv::NORM_INF)));
    }
    EXPECT_GT(compared, 1000);
    EXPECT_LT(worst, 1e-5);
  }
}

TEST(CameraModels, RaysOutsideTheModelAreRejected) {
  const cv::Vec3d behind(0.1, 0.2, -1.0);
  cv::Point2d p;
  EXPECT_FALSE(PinholeCamera(kPinhole).bearingToPixel(behind, p));
  EXPECT_FALSE(PinholeCamera(kPinhole).bearingToPixel({1, 0, 0}, p));
  EXPECT_FALSE(RadTanCamera(RadTanParams{kPinhole, -0.29, 0.08}).bearingToPixel(behind, p));
  // Double sphere with alpha > 0.5: z > -w2 |X| with w2 = 0.632 for these numbers
  // (w1 = (1 - a) / a, w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1)).
  const DoubleSphereCamera ds(DoubleSphereParams{kFisheye, -0.244, 0.566});
  const double w1 = (1 - 0.566) / 0.566, w2 = (w1 - 0.244) / std::sqrt(2 * w1 * -0.244 + 0.244 * 0.244 + 1);
  const double edge = std::acos(-w2);
  EXPECT_TRUE(ds.bearingToPixel({std::sin(edge - 1e-3), 0, std::cos(edge - 1e-3)}, p));
  EXPECT_FALSE(ds.bearingToPixel({std::sin(edge + 1e-3), 0, std::cos(edge + 1e-3)}, p));
  // UCM with alpha > 1 sees less than a hemisphere: cos(theta) > (alpha - 1) / alpha.
  const UnifiedCamera ucm(UnifiedParams{kFisheye, 1.2, 1.0});
  const double ucmEdge = std::acos(0.2 / 1.2);
  EXPECT_TRUE(ucm.bearingToPixel({std::sin(ucmEdge - 1e-3), 0, std::cos(ucmEdge - 1e-3)}, p));
  EXPECT_FALSE(ucm.bearingToPixel({std::sin(ucmEdge + 1e-3), 0, std::cos(ucmEdge + 1e-3)}, p));
  EXPECT_FALSE(OcamCamera(lafidaParams()).bearingToPixel({0, 0, -1}, p));
}

// A ray's length is free (Camera::bearingToPixel): at every length a double holds, every model
// gives the unit ray's pixel, or false exactly where the unit ray does, and d pixel / d bearing
// scales as 1 / length. Lengths 1e-120 to 1e120 reach the models unchanged (a largest component
// in [2^-400, 2^400]); the others, whose squared components would overflow or underflow, are
// scaled into that band by a power of two. The rays: three directions, three the models refuse
// (behind, sideways) and those of a 48-pixel grid of valid pixels.
TEST(CameraModels, ExtremeRayLengthsGiveTheUnitRaysPixel) {
  int compared = 0;
  for (const NamedCamera& c : allCameras()) {
    SCOPED_TRACE(c.name);
    const Camera& camera = *c.camera;
    std::vector<cv::Vec3d> rays{{1, 1, 1}, {0, 0, 1}, {0.3, -0.2, 1}, {0.3, -0.2, -1}, {0, 0, -1}, {1, 0, 0}};
    const cv::Size size = camera.imageSize();
    for (double v = 0.0; v <= size.height - 1.0; v += 48.0)
      for (double u = 0.0; u <= size.width - 1.0; u += 48.0) {
        cv::Vec3d b;
        if (camera.isValid({u, v}) && camera.pixelToBearing({u, v}, b)) rays.push_back(b);
      }
    for (const cv::Vec3d& ray : rays) {
      cv::Point2d unit;
      cv::Matx23d unitJacobian;
      const bool seen = camera.bearingToPixelJacobian(ray / cv::norm(ray), unit, unitJacobian);
      if (ray == cv::Vec3d(0, 0, 1)) {
        EXPECT_TRUE(seen) << "the optical axis";
      }
      // Scaled to a largest component of 1 first (exactly 1 for that component), so that the
      // largest component is `length`.
      const cv::Vec3d direction = ray / cv::norm(ray, cv::NORM_INF);
      const double norm = cv::norm(direction);
      for (const double length :
           {1e-300, 1e-160, 1e-120, 1e-100, 1e-20, 1e20, 1e100, 1e120, 1e160, 1e300, 1.7e308}) {
        const cv::Vec3d b = direction * length;
        cv::Point2d p, q;
        cv::Matx23d jacobian;
        ASSERT_EQ(camera.bearingToPixel(b, p), seen) << length << " " << ray;
        ASSERT_EQ(camera.bearingToPixelJacobian(b, q, jacobian), seen) << length << " " << ray;
        if (!seen) continue;
        EXPECT_EQ(p, q) << length << " " << ray;
        EXPECT_LT(cv::norm(p - unit), 1e-9) << length << " " << ray << " -> " << p << ", unit ray " << unit;
        // |b| = length * norm, multiplied in turn since it overflows at 1.7e308.
        const cv::Matx23d unitScale = jacobian * length * norm;
        EXPECT_LT(cv::norm(unitScale - unitJacobian) / cv::norm(unitJacobian), 1e-9)
            << length << " " << ray << ": " << jacobian << " at the unit ray " << unitJacobian;
        ++compared;
      }
    }
    // Subnormal rays, of directions whose components stay exact there: the pixel (their
    // d pixel / d bearing exceeds double's range).
    for (const cv::Vec3d& ray : {cv::Vec3d(1, 1, 1), cv::Vec3d(0, 0, 1), cv::Vec3d(0.375, -0.25, 1),
                                 cv::Vec3d(0.375, -0.25, -1), cv::Vec3d(1, 0, 0)}) {
      cv::Point2d unit, p;
      const bool seen = camera.bearingToPixel(ray / cv::norm(ray), unit);
      for (const int exponent : {-1022, -1060, -1071}) {
        const cv::Vec3d b(std::ldexp(ray[0], exponent), std::ldexp(ray[1], exponent), std::ldexp(ray[2], exponent));
        ASSERT_EQ(camera.bearingToPixel(b, p), seen) << b;
        if (seen) {
          EXPECT_LT(cv::norm(p - unit), 1e-9) << b << " -> " << p << ", unit ray " << unit;
        }
      }
    }
    // Rays without a direction.
    cv::Point2d p;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const cv::Vec3d& b : {cv::Vec3d(0, 0, 0), cv::Vec3d(nan, 0, 1), cv::Vec3d(0.1, nan, 1e-300),
                               cv::Vec3d(1e300, 0, nan)})
      EXPECT_FALSE(camera.bearingToPixel(b, p)) << b;
  }
  EXPECT_GT(compared, 10000);
}

TEST(CameraModels, PinholePrincipalPointAndClosedForm) {
  const PinholeCamera cam(CameraIntrinsics{640, 480, 500.0, 400.0, 320.0, 240.0});
  cv::Vec3d b;
  ASSERT_TRUE(cam.pixelToBearing({320.0, 240.0}, b));
  EXPECT_EQ(b, cv::Vec3d(0, 0, 1));
  // (u, v) = (820, 640): normalised (1, 1) -> bearing (1, 1, 1) / sqrt(3).
  ASSERT_TRUE(cam.pixelToBearing({820.0, 640.0}, b));
  EXPECT_NEAR(b[0], 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(b[1], 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(b[2], 1 / std::sqrt(3.0), 1e-15);
  EXPECT_FALSE(cam.isValid({820.0, 640.0}));
  EXPECT_TRUE(cam.isValid({0.0, 479.0}));
  EXPECT_FALSE(cam.isValid({-0.01, 10.0}));
  EXPECT_FALSE(cam.isValid({std::nan(""), 10.0}));
  EXPECT_DOUBLE_EQ(cam.tangentPlaneScale(), 450.0);
}

TEST(CameraModels, RadialWithZeroXiIsExactlyThePinhole) {
  const PinholeCamera pinhole(kPinhole);
  const RadialCamera radial(RadialParams{kPinhole, 0.0});
  for (double u = 0; u < 754; u += 37.3)
    for (double v = 0; v < 480; v += 29.1) {
      cv::Vec3d a, b;
      ASSERT_TRUE(pinhole.pixelToBearing({u, v}, a));
      ASSERT_TRUE(radial.pixelToBearing({u, v}, b));
      EXPECT_EQ(a, b);
      cv::Point2d pa, pb;
      const cv::Vec3d ray(u - 300.0, v - 200.0, 250.0);
      ASSERT_TRUE(pinhole.bearingToPixel(ray, pa));
      ASSERT_TRUE(radial.bearingToPixel(ray, pb));
      EXPECT_EQ(pa, pb);
    }
}

// The paper's xi = -2^-6 in units of 100 px: the numbers quoted in camera/radial.hpp, computed
// here from the division model m = m_d / (1 + xi |m_d|^2) by hand.
TEST(CameraModels, RadialPaperDistortionMagnitude) {
  const double xi = -1.0 / 64;
  const RadialCamera radial(RadialParams{kPinhole, xi, 100.0});
  const PinholeCamera pinhole(kPinhole);
  const cv::Point2d corner(0, 0), centre(kPinhole.cx, kPinhole.cy);
  const double rd = cv::norm(corner - centre) / 100.0;
  const double ru = rd / (1 + xi * rd * rd);
  cv::Vec3d b;
  cv::Point2d undistorted;
  ASSERT_TRUE(radial.pixelToBearing(corner, b));
  ASSERT_TRUE(pinhole.bearingToPixel(b, undistorted));
  EXPECT_NEAR(cv::norm(undistorted - centre), 100.0 * ru, 1e-9);
  EXPECT_NEAR(cv::norm(undistorted - corner), 210.0, 0.5);
  // A point whose undistorted image is the corner moves 91 px inwards.
  ASSERT_TRUE(pinhole.pixelToBearing(corner, b));
  cv::Point2d distorted;
  ASSERT_TRUE(radial.bearingToPixel(b, distorted));
  EXPECT_NEAR(cv::norm(distorted - corner), 91.2, 0.5);
  EXPECT_NEAR(cv::norm(distorted - centre) / 100.0, 2 * rd / (1 + std::sqrt(1 - 4 * xi * rd * rd)), 1e-9);
}

TEST(CameraModels, RadialLimitRadius) {
  // Barrel: pixels beyond |m_d| = 1/sqrt(-xi) = 8 units (800 px) have no inverse.
  const RadialCamera barrel(RadialParams{{2000, 2000, 400, 400, 0, 0}, -1.0 / 64, 100.0});
  cv::Vec3d b;
  EXPECT_TRUE(barrel.pixelToBearing({799.0, 0}, b));
  EXPECT_FALSE(barrel.pixelToBearing({801.0, 0}, b));
  EXPECT_TRUE(barrel.isValid({799.0, 0}));
  EXPECT_FALSE(barrel.isValid({801.0, 0}));
  // Pincushion: rays beyond |m| = 1 / (2 sqrt(xi)) = 2.5 units (250 px) cannot be projected.
  const RadialCamera pincushion(RadialParams{{2000, 2000, 400, 400, 0, 0}, 0.04, 100.0});
  cv::Point2d p;
  EXPECT_TRUE(pincushion.bearingToPixel({249.0, 0, 400.0}, p));
  EXPECT_FALSE(pincushion.bearingToPixel({251.0, 0, 400.0}, p));
}

TEST(CameraModels, KannalaBrandtEquidistantClosedForm) {
  const KannalaBrandtCamera kb(KannalaBrandtParams{{800, 800, 200, 200, 400, 400}, 0, 0, 0, 0});
  // Equidistant: a pixel at distance f * theta sees the ray at angle theta, up to 180 degrees.
  for (double theta : {0.3, 1.0, CV_PI / 2, 1.9}) {
    cv::Vec3d b;
    ASSERT_TRUE(kb.pixelToBearing({400 + 200 * theta, 400}, b));
    EXPECT_NEAR(std::acos(b[2]), theta, 1e-12);
    EXPECT_NEAR(b[1], 0.0, 1e-15);
  }
  // A polynomial that turns back: theta_d' = 1 - 0.9 theta^2 = 0 at theta = 1/sqrt(0.9).
  const KannalaBrandtCamera folding(KannalaBrandtParams{kFisheye, -0.3, 0, 0, 0});
  EXPECT_NEAR(folding.maxTheta(), 1 / std::sqrt(0.9), 1e-9);
}

TEST(CameraModels, UnifiedAndDoubleSphereReduceToPinhole) {
  const PinholeCamera pinhole(kFisheye);
  const UnifiedCamera ucm(UnifiedParams{kFisheye, 0.0, 1.0});
  const DoubleSphereCamera ds(DoubleSphereParams{kFisheye, 0.0, 0.0});
  EXPECT_EQ(ucm.modelName(), "ucm");
  EXPECT_EQ(UnifiedCamera(UnifiedParams{kFisheye, 0.5, 1.2}).modelName(), "eucm");
  for (const cv::Vec3d& ray : {cv::Vec3d(0.3, -0.2, 1.0), cv::Vec3d(-0.7, 0.4, 1.0)}) {
    cv::Point2d a, b, c;
    ASSERT_TRUE(pinhole.bearingToPixel(ray, a));
    ASSERT_TRUE(ucm.bearingToPixel(ray, b));
    ASSERT_TRUE(ds.bearingToPixel(ray, c));
    EXPECT_LT(cv::norm(a - b), 1e-9);
    EXPECT_LT(cv::norm(a - c), 1e-9);
  }
}

TEST(CameraModels, RadTanMonotonicLimit) {
  // k1 = -0.5 only: r_d' = 1 - 1.5 r^2 vanishes at r = sqrt(2/3).
  const RadTanCamera cam(RadTanParams{{4000, 4000, 500, 500, 2000, 2000}, -0.5, 0, 0, 0, 0});
  const double rMax = std::sqrt(2.0 / 3.0);
  EXPECT_NEAR(cam.maxUndistortedRadius(), rMax, 1e-9);
  const double rdMax = rMax * (1 - 0.5 * rMax * rMax);
  EXPECT_TRUE(cam.isValid({2000 + 500 * rdMax - 0.5, 2000}));
  EXPECT_FALSE(cam.isValid({2000 + 500 * rdMax + 0.5, 2000}));
  cv::Point2d p;
  EXPECT_TRUE(cam.bearingToPixel({rMax - 1e-3, 0, 1}, p));
  EXPECT_FALSE(cam.bearingToPixel({rMax + 1e-3, 0, 1}, p));
}

// The rational factor's limit: a ray beyond maxRadius on the z = 1 plane does not project, and
// the pixels past its image are not valid.
TEST(CameraModels, RadTanMaxRadiusLimitsTheRational) {
  RadTanParams p{{4000, 4000, 500, 500, 2000, 2000}, 0.1, 0, 0, 0, 0};
  p.k4 = 0.2;
  p.maxRadius = 1.5;
  const RadTanCamera cam(p);
  EXPECT_DOUBLE_EQ(cam.maxUndistortedRadius(), 1.5);
  cv::Point2d px;
  EXPECT_TRUE(cam.bearingToPixel({1.5 - 1e-6, 0, 1}, px));
  EXPECT_FALSE(cam.bearingToPixel({1.5 + 1e-6, 0, 1}, px));
  // radial(r^2) = (1 + 0.1 r^2) / (1 + 0.2 r^2): r = 1 distorts to 1.1 / 1.2.
  ASSERT_TRUE(cam.bearingToPixel({1, 0, 1}, px));
  EXPECT_NEAR(px.x, 2000 + 500 * 1.1 / 1.2, 1e-9);
  const double rdMax = 1.5 * (1 + 0.1 * 2.25) / (1 + 0.2 * 2.25);
  EXPECT_TRUE(cam.isValid({2000 + 500 * rdMax - 0.5, 2000}));
  EXPECT_FALSE(cam.isValid({2000 + 500 * rdMax + 0.5, 2000}));
}

// Mei's model without distortion is the unified model: UCM with alpha = xi / (1 + xi) and the
// focal length f / (1 + xi); with xi = 0 too, the pinhole camera.
TEST(CameraModels, OmniReducesToUnifiedAndPinhole) {
  const double xi = 0.8;
  const OmniCamera omni(OmniParams{{752, 480, 833.0, 830.0, 373.8, 253.7}, xi});
  const UnifiedCamera ucm(UnifiedParams{{752, 480, 833.0 / (1 + xi), 830.0 / (1 + xi), 373.8, 253.7}, xi / (1 + xi), 1.0});
  const OmniCamera flat(OmniParams{kPinhole, 0.0});
  const PinholeCamera pinhole(kPinhole);
  EXPECT_DOUBLE_EQ(omni.tangentPlaneScale(), ucm.tangentPlaneScale());
  for (double u = 0; u < 752; u += 37)
    for (double v = 0; v < 480; v += 29) {
      cv::Vec3d a, b;
      ASSERT_EQ(omni.pixelToBearing({u, v}, a), ucm.pixelToBearing({u, v}, b));
      if (ucm.isValid({u, v})) {
        EXPECT_LT(mdbrief::testing::angleBetween(a, b), 1e-12);
      }
      ASSERT_TRUE(flat.pixelToBearing({u, v}, a));
      ASSERT_TRUE(pinhole.pixelToBearing({u, v}, b));
      EXPECT_LT(mdbrief::testing::angleBetween(a, b), 1e-12);
    }
  // Beyond 90 degrees for xi > 0, up to cos(theta) = -xi (xi <= 1; the plane's radius grows
  // without bound there, so the search limit of |m| = 50 cuts first) or -1 / xi (xi > 1).
  cv::Point2d p;
  EXPECT_TRUE(omni.bearingToPixel({std::sqrt(1 - 0.7 * 0.7), 0, -0.7}, p));
  EXPECT_FALSE(omni.bearingToPixel({std::sqrt(1 - 0.81 * 0.81), 0, -0.81}, p));
  const OmniCamera wide(OmniParams{{752, 480, 500, 500, 376, 240}, 2.0});
  EXPECT_TRUE(wide.bearingToPixel({std::sqrt(1 - 0.49 * 0.49), 0, -0.49}, p));
  EXPECT_FALSE(wide.bearingToPixel({std::sqrt(1 - 0.51 * 0.51), 0, -0.51}, p));
}

TEST(CameraModels, OcamConventions) {
  const OcamCamera cam(lafidaParams());
  EXPECT_DOUBLE_EQ(cam.tangentPlaneScale(), 209.200757992065);
  // The centre sees the optical axis; a pixel to the right of the centre (larger column) sees
  // a ray with x > 0, one below it a ray with y > 0 (the OCamCalib frame is rotated into ours).
  cv::Vec3d b;
  ASSERT_TRUE(cam.pixelToBearing({392.219508388648, 243.494438476351}, b));
  EXPECT_NEAR(cv::norm(b - cv::Vec3d(0, 0, 1)), 0.0, 1e-12);
  ASSERT_TRUE(cam.pixelToBearing({492.0, 243.494438476351}, b));
  EXPECT_GT(b[0], 0.4);
  EXPECT_NEAR(b[1], 0.0, 0.01);
  ASSERT_TRUE(cam.pixelToBearing({392.219508388648, 343.0}, b));
  EXPECT_GT(b[1], 0.4);
  EXPECT_NEAR(b[0], 0.0, 0.01);
  // Image circle: v0 + 22 px about the centre.
  EXPECT_TRUE(cam.isValid({392.2 + 265.0, 243.5}));
  EXPECT_FALSE(cam.isValid({392.2 + 266.0, 243.5}));
  // 90 degrees from the axis is where f(rho) changes sign (z_o = 0).
  ASSERT_TRUE(cam.pixelToBearing({392.219508388648 + 296.0, 243.494438476351}, b));
  EXPECT_NEAR(b[2], 0.0, 0.02);
}

// isValid() decides its two distance limits (the image circle, the model's range) as std::hypot
// does, also within a few ulps of them, where a square sum and hypot can disagree.
TEST(CameraModels, OcamValidAreaBoundariesAsHypotDecidesThem) {
  OcamParams circle = lafidaParams();  // the image circle inside the image left and right
  OcamParams range = lafidaParams();   // a forward polynomial that turns at rho ~ 190 px
  range.forward = {-209.2, 0.0, 0.00213741670953883, -2e-5};
  range.validRadius = 0.0;
  size_t inside = 0, outside = 0;
  for (const OcamParams& p : {circle, range}) {
    const OcamCamera cam(p);
    const double invDet = 1.0 / (p.c - p.d * p.e);
    const auto rho = [&](double dr, double dc) {
      return std::hypot(invDet * (dr - p.d * dc), invDet * (-p.e * dr + p.c * dc));
    };
    for (int a = 0; a < 90; ++a) {
      const double dx = std::cos(a * 0.07), dy = 0.3 * std::sin(a * 0.07);
      // Along the ray to where the point's own distance is the limit.
      const double t = p.validRadius > 0 ? p.validRadius / std::hypot(dx, dy) : cam.maxRho() / rho(dy, dx);
      for (int k = -40; k <= 40; ++k) {
        const cv::Point2d px(p.u0 + dx * t * (1 + k * 1e-16), p.v0 + dy * t * (1 + k * 1e-16));
        const double dr = px.y - p.v0, dc = px.x - p.u0;
        const bool expected = px.x >= 0 && px.x <= p.width - 1 && px.y >= 0 && px.y <= p.height - 1 &&
                              !(p.validRadius > 0 && std::hypot(dr, dc) > p.validRadius) &&
                              rho(dr, dc) < cam.maxRho();
        ASSERT_EQ(cam.isValid(px), expected) << "angle step " << a << ", k " << k;
        (expected ? inside : outside) += 1;
      }
    }
  }
  EXPECT_GT(inside, 2000u);
  EXPECT_GT(outside, 2000u);
}

// resized() must describe the image cv::resize produces: pixel centres move as
// u' = (u + 0.5) s - 0.5. Checked on every model with an aspect-changing size, and the way back.
TEST(CameraModels, ResizedFollowsTheResampledImage) {
  for (const NamedCamera& c : allCameras()) {
    SCOPED_TRACE(c.name);
    const cv::Size size = c.camera->imageSize();
    const cv::Size small(size.width * 7 / 10, size.height * 11 / 20);
    const double sx = double(small.width) / size.width, sy = double(small.height) / size.height;
    const auto resized = c.camera->resized(small);
    EXPECT_EQ(resized->imageSize(), small);
    EXPECT_EQ(resized->modelName(), c.camera->modelName());
    int checked = 0;
    for (double u = 0; u < size.width; u += 23.0)
      for (double v = 0; v < size.height; v += 19.0) {
        cv::Vec3d b, b2;
        if (!c.camera->isValid({u, v}) || !c.camera->pixelToBearing({u, v}, b)) continue;
        cv::Point2d q;
        ASSERT_TRUE(resized->bearingToPixel(b, q));
        EXPECT_NEAR(q.x, (u + 0.5) * sx - 0.5, 1e-6);
        EXPECT_NEAR(q.y, (v + 0.5) * sy - 0.5, 1e-6);
        ASSERT_TRUE(resized->pixelToBearing(q, b2));
        EXPECT_LT(mdbrief::testing::angleBetween(b, b2), 1e-9);
        ++checked;
      }
    EXPECT_GT(checked, 50);
    const auto back = resized->resized(size);
    for (double u = 5; u < size.width; u += 97.0) {
      cv::Vec3d a, b;
      const cv::Point2d p(u, size.height / 2.0);
      if (!c.camera->pixelToBearing(p, a)) continue;
      ASSERT_TRUE(back->pixelToBearing(p, b));
      EXPECT_LT(mdbrief::testing::angleBetween(a, b), 1e-9);
    }
    EXPECT_THROW(c.camera->resized({0, 10}), std::invalid_argument);
  }
}

void expectInvalid(const std::function<void()>& make, const std::string& parameter) {
  try {
    make();
    ADD_FAILURE() << "no exception for " << parameter;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'" + parameter + "'"), std::string::npos) << e.what();
  }
}

TEST(CameraModels, ConstructorsRejectBadParameters) {
  CameraIntrinsics k = kPinhole;
  k.fx = 0;
  expectInvalid([&] { PinholeCamera c(k); }, "fx");
  k = kPinhole;
  k.height = -3;
  expectInvalid([&] { PinholeCamera c(k); }, "height");
  k = kPinhole;
  k.cy = std::nan("");
  expectInvalid([&] { KannalaBrandtCamera c(KannalaBrandtParams{k}); }, "cy");
  expectInvalid([&] { RadialCamera c(RadialParams{kPinhole, std::nan("")}); }, "xi");
  expectInvalid([&] { RadialCamera c(RadialParams{kPinhole, 0.0, -1.0}); }, "unit_px");
  expectInvalid([&] { DoubleSphereCamera c(DoubleSphereParams{kPinhole, 0.0, 1.5}); }, "alpha");
  expectInvalid([&] { DoubleSphereCamera c(DoubleSphereParams{kPinhole, -1.0, 0.5}); }, "xi");
  expectInvalid([&] { UnifiedCamera c(UnifiedParams{kPinhole, -0.1, 1.0}); }, "alpha");
  expectInvalid([&] { UnifiedCamera c(UnifiedParams{kPinhole, 0.5, 0.0}); }, "beta");
  expectInvalid([&] { RadTanCamera c(RadTanParams{kPinhole, 0, INFINITY}); }, "k2");
  RadTanParams r{kPinhole};
  r.k5 = NAN;
  expectInvalid([&] { RadTanCamera c(r); }, "k5");
  r = RadTanParams{kPinhole};
  r.maxRadius = -1;
  expectInvalid([&] { RadTanCamera c(r); }, "max_radius");
  expectInvalid([&] { OmniCamera c(OmniParams{kPinhole, -0.1}); }, "xi");
  expectInvalid([&] { OmniCamera c(OmniParams{kPinhole, 1.0, 0, 0, INFINITY}); }, "p1");
  OcamParams o = lafidaParams();
  o.forward = {-200.0};
  expectInvalid([&] { OcamCamera c(o); }, "forward");
  o = lafidaParams();
  o.forward[0] = 209.2;
  expectInvalid([&] { OcamCamera c(o); }, "forward[0]");
  o = lafidaParams();
  o.inverse = {1.0};
  expectInvalid([&] { OcamCamera c(o); }, "inverse");
  o = lafidaParams();
  o.c = 0.0;
  o.d = 1.0;
  o.e = 0.0;
  expectInvalid([&] { OcamCamera c(o); }, "c");
  o = lafidaParams();
  o.validRadius = -1;
  expectInvalid([&] { OcamCamera c(o); }, "valid_radius");
}

}  // namespace
