// The planes dBRIEF places its tests on (mdbrief/camera/tangent_plane.hpp): the local plane, tangent at
// the keypoint's ray, turns with the camera, so a turned lens sees the same footprint on a
// structure wherever the structure appears; the paper's plane z = lambda does not.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/calib3d.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/camera/tangent_plane.hpp"
#include "test_data.hpp"

namespace mdbrief {
namespace {

CameraPtr fisheye() {
  return loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
}

cv::Vec3d rayOf(const TangentPlaneFrame& f, const cv::Point2d& offset) {
  const cv::Vec3d p = f.origin + f.e1 * offset.x + f.e2 * offset.y;
  return p / cv::norm(p);
}

// The largest angle (degrees) between the rays of a 32x32 footprint at `a` carried by the
// rotation and the rays of the footprint at the turned pixel, after the best in-plane turn of
// the second footprint (dBRIEF measures its orientation on the plane, so that turn is free).
double footprintMismatchDeg(const Camera& camera, const cv::Point2d& a, const cv::Matx33d& rotation, bool local) {
  cv::Vec3d ra;
  if (!camera.pixelToBearing(a, ra)) return NAN;
  cv::Point2d b;
  if (!camera.bearingToPixel(rotation * ra, b)) return NAN;
  const auto fa = tangentPlaneAt(camera, a, 180.0, local);
  const auto fb = tangentPlaneAt(camera, b, 180.0, local);
  if (!fa || !fb) return NAN;
  // The in-plane turn that carries the footprint's x axis.
  const cv::Vec3d axis = rotation * rayOf(*fa, {16, 0});
  const cv::Vec3d offset = axis * (fb->origin.dot(fb->origin) / axis.dot(fb->origin)) - fb->origin;
  const double turn = std::atan2(offset.dot(fb->e2), offset.dot(fb->e1));
  double worst = 0;
  for (double u = -16; u <= 16; u += 8)
    for (double v = -16; v <= 16; v += 8) {
      const cv::Vec3d carried = rotation * rayOf(*fa, {u, v});
      const cv::Point2d turned(u * std::cos(turn) - v * std::sin(turn), u * std::sin(turn) + v * std::cos(turn));
      const cv::Vec3d there = rayOf(*fb, turned);
      worst = std::max(worst, std::atan2(cv::norm(carried.cross(there)), carried.dot(there)) * 180.0 / CV_PI);
    }
  return worst;
}

TEST(TangentPlane, TheLocalFootprintTurnsWithTheLens) {
  const CameraPtr camera = fisheye();
  const cv::Size size = camera->imageSize();
  int checked = 0;
  double localWorst = 0, globalWorst = 0;
  for (const cv::Vec3d& angles : {cv::Vec3d(0.2, 0.1, 0.3), cv::Vec3d(-0.5, 0.2, 1.0), cv::Vec3d(0.1, -0.7, -0.4)}) {
    cv::Matx33d rotation;
    cv::Rodrigues(angles, rotation);
    for (int y = 60; y < size.height; y += 60)
      for (int x = 60; x < size.width; x += 60) {
        const double local = footprintMismatchDeg(*camera, {double(x), double(y)}, rotation, true);
        if (std::isnan(local)) continue;
        ++checked;
        localWorst = std::max(localWorst, local);
        const double global = footprintMismatchDeg(*camera, {double(x), double(y)}, rotation, false);
        if (!std::isnan(global)) globalWorst = std::max(globalWorst, global);
      }
  }
  ASSERT_GT(checked, 50);
  // A footprint spans about 10 degrees of rays: the local plane carries it to within numerical
  // noise, the paper's plane deforms it by a sizeable part of its own size.
  EXPECT_LT(localWorst, 1e-6);
  EXPECT_GT(globalWorst, 1.0);
}

TEST(TangentPlane, LocalAndPapersPlanesAgreeOnTheOpticalAxis) {
  CameraIntrinsics k;
  k.width = 640, k.height = 480, k.fx = k.fy = 500, k.cx = 320, k.cy = 240;
  const PinholeCamera pinhole(k);
  const auto local = tangentPlaneAt(pinhole, {320, 240}, 180.0, true);
  const auto paper = tangentPlaneAt(pinhole, {320, 240}, 80.0, false);
  ASSERT_TRUE(local && paper);
  EXPECT_LT(cv::norm(local->jacobian - paper->jacobian), 1e-9);
  EXPECT_LT(cv::norm(local->jacobian - cv::Matx22d::eye()), 1e-9);  // lambda = focal length
}

// Off the axis a pinhole stretches a plane facing the ray by 1 / cos^2 of the incidence radially
// and 1 / cos tangentially: the local plane's Jacobian says so; the paper's plane is the image.
TEST(TangentPlane, LocalPlaneOfAPinholeMeasuresItsPerspectiveStretch) {
  CameraIntrinsics k;
  k.width = 1000, k.height = 600, k.fx = k.fy = 400, k.cx = 500, k.cy = 300;
  const PinholeCamera pinhole(k);
  const double x = 500 + 400 * std::tan(40 * CV_PI / 180);  // 40 degrees along the image's x axis
  const auto local = tangentPlaneAt(pinhole, {x, 300}, 180.0, true);
  const auto paper = tangentPlaneAt(pinhole, {x, 300}, 80.0, false);
  ASSERT_TRUE(local && paper);
  const double c = std::cos(40 * CV_PI / 180);
  // Central differences of half a pixel: exact up to about 1e-6.
  EXPECT_NEAR(local->jacobian(0, 0), 1 / (c * c), 1e-5);
  EXPECT_NEAR(local->jacobian(1, 1), 1 / c, 1e-5);
  EXPECT_NEAR(paper->jacobian(0, 0), 1.0, 1e-9);
  EXPECT_NEAR(paper->jacobian(1, 1), 1.0, 1e-9);
}

// Beyond 90 degrees the paper's plane does not exist; the local one does, within the bound.
TEST(TangentPlane, OnlyTheLocalPlaneReachesBeyondNinetyDegrees) {
  KannalaBrandtParams p;  // equidistant: 120 px per radian, 95 degrees at 199 px from the centre
  p.intrinsics.width = 752, p.intrinsics.height = 480;
  p.intrinsics.fx = p.intrinsics.fy = 120, p.intrinsics.cx = 376, p.intrinsics.cy = 240;
  const KannalaBrandtCamera camera(p);
  cv::Point2d rim;
  const double a = 95 * CV_PI / 180;
  ASSERT_TRUE(camera.bearingToPixel({std::sin(a), 0, std::cos(a)}, rim));
  ASSERT_TRUE(camera.isValid(rim)) << rim;
  EXPECT_TRUE(tangentPlaneAt(camera, rim, 180.0, true));
  EXPECT_FALSE(tangentPlaneAt(camera, rim, 90.0, true));
  EXPECT_FALSE(tangentPlaneAt(camera, rim, 180.0, false));
}

}  // namespace
}  // namespace mdbrief
