// BRIEF / mdBRIEF semantics on images whose answer is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "mdbrief/describe/descriptor.hpp"

namespace mdbrief {
namespace {

ComparisonSet randomComparisons(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> u(-15, 14);
  ComparisonSet set{"test_random", {}, {}};
  while (static_cast<int>(set.tests.size()) < n) {
    ComparisonPair t{int8_t(u(rng)), int8_t(u(rng)), int8_t(u(rng)), int8_t(u(rng))};
    if (t.x1 != t.x2 || t.y1 != t.y2) set.tests.push_back(t);
  }
  return set;
}

// I(x, y) = x: bilinear interpolation of a ramp is exact, so test d is 1 iff its first point
// lies left of its second, after rotation by the keypoint angle.
cv::Mat horizontalRamp() {
  cv::Mat img(256, 256, CV_8U);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) img.at<uchar>(y, x) = static_cast<uchar>(x);
  return img;
}

bool bit(const cv::Mat& desc, int row, int d) { return (desc.at<uchar>(row, d / 8) >> (d % 8)) & 1; }

// x coordinate offset of a test point after rotating it by deg.
double rotatedX(int qx, int qy, double deg) {
  const double a = deg * CV_PI / 180.0;
  return std::cos(a) * qx - std::sin(a) * qy;
}

DescriptorOptions briefOptions(int bits) {
  DescriptorOptions o;
  o.kind = DescriptorKind::Brief;
  o.bits = bits;  // the default smoothing keeps a ramp a ramp away from the border
  return o;
}

TEST(Brief, BitsFollowTheTestsAndTheBitOrderOnARamp) {
  const ComparisonSet tests = randomComparisons(256, 1);
  const DescriptorExtractor brief(nullptr, briefOptions(256), tests);
  for (const float angle : {-1.f, 0.f, 90.f, 33.f, 210.f}) {
    std::vector<cv::KeyPoint> kps{cv::KeyPoint(128.3f, 127.6f, 31.f, angle, 1.f, 0)};
    cv::Mat desc;
    brief.compute(horizontalRamp(), kps, desc);
    ASSERT_EQ(desc.rows, 1);
    ASSERT_EQ(desc.cols, 32);
    const double deg = angle < 0 ? 0.0 : angle;
    int checked = 0;
    for (int d = 0; d < 256; ++d) {
      const ComparisonPair& t = tests.tests[d];
      const double dx = rotatedX(t.x2, t.y2, deg) - rotatedX(t.x1, t.y1, deg);
      if (std::abs(dx) < 0.1) continue;  // closer than the 1/32 px sampling grid can resolve
      EXPECT_EQ(bit(desc, 0, d), dx > 0) << "test " << d << " angle " << angle;
      ++checked;
    }
    EXPECT_GT(checked, 230);
  }
}

TEST(Brief, ShorterDescriptorIsThePrefixOfTheLongerOne) {
  const ComparisonSet tests = randomComparisons(512, 2);
  cv::Mat img(200, 300, CV_8U);
  cv::randu(img, 0, 256);
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 40; ++i) kps.emplace_back(40.f + 5.5f * i, 60.f + 2.25f * i, 31.f, 7.f * i, 1.f, i % 2);
  std::vector<cv::KeyPoint> kps512 = kps, kps96 = kps;
  cv::Mat d512, d96;
  DescriptorExtractor(nullptr, briefOptions(512), tests).compute(img, kps512, d512);
  DescriptorExtractor(nullptr, briefOptions(96), tests).compute(img, kps96, d96);
  ASSERT_EQ(d512.rows, d96.rows);
  ASSERT_GT(d96.rows, 0);
  EXPECT_EQ(cv::norm(d512.colRange(0, 12), d96, cv::NORM_L1), 0.0);
}

TEST(Brief, KeypointsWhoseTestsLeaveTheImageAreDroppedConsistently) {
  const ComparisonSet tests = randomComparisons(256, 3);
  cv::Mat img(120, 160, CV_8U);
  cv::randu(img, 0, 256);
  std::vector<cv::KeyPoint> kps{
      cv::KeyPoint(80, 60, 31, 45, 1, 0),    // central: kept
      cv::KeyPoint(2, 60, 31, 0, 1, 0),      // at the left border: dropped
      cv::KeyPoint(80, 118, 31, 0, 1, 0),    // at the bottom border: dropped
      cv::KeyPoint(1e30f, 5, 31, 0, 1, 0),   // absurd coordinates: dropped, no overflow
      cv::KeyPoint(NAN, 5, 31, 0, 1, 0),     // not a number: dropped
      cv::KeyPoint(70, 50, 31, 300, 1, 1),   // octave 1 (level 133x100): kept
      cv::KeyPoint(150, 60, 31, 0, 1, 1),    // right border at octave 1: dropped
  };
  cv::Mat desc;
  DescriptorExtractor(nullptr, briefOptions(256), tests).compute(img, kps, desc);
  ASSERT_EQ(kps.size(), 2u);
  EXPECT_EQ(desc.rows, 2);
  EXPECT_FLOAT_EQ(kps[0].pt.x, 80.f);
  EXPECT_FLOAT_EQ(kps[1].pt.x, 70.f);
}

// The footprint follows the size, not the octave: sizes that are not positive finite numbers
// are dropped, any octave is accepted, and nothing is read outside the image.
TEST(Brief, KeypointsFromOutsideAreDescribedBySizeOrDropped) {
  const ComparisonSet tests = randomComparisons(256, 4);
  cv::Mat img(120, 160, CV_8U, cv::Scalar(10));
  const ImagePyramid pyramid(img, PyramidOptions{}, 2);
  std::vector<cv::KeyPoint> kps{
      cv::KeyPoint(80, 60, 31, 0, 1, 5),          // octave beyond the pyramid: ignored, kept
      cv::KeyPoint(80, 60, 31, 0, 1, -3),         // negative octave: ignored, kept
      cv::KeyPoint(81, 60, 0, 0, 1, 0),           // size 0: dropped
      cv::KeyPoint(82, 60, -31, 0, 1, 0),         // negative size: dropped
      cv::KeyPoint(83, 60, NAN, 0, 1, 0),         // NaN size: dropped
      cv::KeyPoint(84, 60, INFINITY, 0, 1, 0),    // infinite size: dropped
      cv::KeyPoint(85, 60, 400, 0, 1, 0),         // footprint larger than the image: dropped
      cv::KeyPoint(-40, 60, 31, 0, 1, 0),         // outside the image: dropped
  };
  cv::Mat desc;
  ASSERT_NO_THROW(DescriptorExtractor(nullptr, briefOptions(256), tests).compute(pyramid, kps, desc));
  ASSERT_EQ(kps.size(), 2u);
  EXPECT_EQ(desc.rows, 2);
  EXPECT_EQ(kps[0].octave, 5);
  EXPECT_EQ(kps[1].octave, -3);
}

// A footprint under one input pixel compares one interpolated value with itself: all zeros,
// all stable, and two such keypoints anywhere would match at distance 0. They are dropped.
TEST(Brief, KeypointsWhoseFootprintIsUnderOnePixelAreDropped) {
  const ComparisonSet tests = randomComparisons(256, 5);
  const ImagePyramid pyramid(horizontalRamp(), PyramidOptions{});
  for (const DescriptorKind kind : {DescriptorKind::Brief, DescriptorKind::MaskedBrief}) {
    for (const double supportScale : {1.0, 4.0}) {
      auto o = briefOptions(256);
      o.kind = kind;
      o.supportScale = supportScale;
      const auto footprint = [&](double pixels) { return static_cast<float>(pixels / supportScale); };
      std::vector<cv::KeyPoint> kps{
          cv::KeyPoint(100, 100, 1e-30f, 0, 1, 0),            // dropped
          cv::KeyPoint(110, 100, footprint(0.99), 0, 1, 0),   // dropped
          cv::KeyPoint(120, 100, footprint(1.0), 0, 1, 0),    // kept
          cv::KeyPoint(130, 100, footprint(31.0), 0, 1, 0),   // kept
      };
      cv::Mat desc, masks;
      DescriptorExtractor(nullptr, o, tests).compute(pyramid, kps, desc, masks);
      ASSERT_EQ(kps.size(), 2u) << toString(kind) << " supportScale " << supportScale;
      EXPECT_EQ(kps[0].pt.x, 120.f);
      EXPECT_EQ(kps[1].pt.x, 130.f);
      EXPECT_TRUE(DescriptorExtractor(nullptr, o, tests)
                      .comparisonPositions(pyramid, cv::KeyPoint(100, 100, 1e-30f, 0, 1, 0))
                      .empty());
    }
  }
}

// The same keypoint at sizes s and 1.2 s samples a footprint 1.2 x wider, whichever levels the
// two sizes fall on; supportScale scales it the same way.
TEST(Brief, FootprintIsProportionalToTheKeypointSize) {
  const ComparisonSet tests = randomComparisons(256, 6);
  const ImagePyramid pyramid(cv::Mat(600, 800, CV_8UC1, cv::Scalar(0)), PyramidOptions{});
  const auto spread = [&](float size, double supportScale) {
    auto o = briefOptions(256);
    o.supportScale = supportScale;
    const auto pos =
        DescriptorExtractor(nullptr, o, tests).comparisonPositions(pyramid, cv::KeyPoint(400, 300, size, 30, 1, 0));
    EXPECT_EQ(pos.size(), 256u);
    double sum = 0;
    for (const auto& [p1, p2] : pos) sum += cv::norm(p1 - cv::Point2f(400, 300)) + cv::norm(p2 - cv::Point2f(400, 300));
    return sum;
  };
  for (const float s : {23.f, 31.f, 40.f, 57.f, 90.f}) {
    EXPECT_NEAR(spread(1.2f * s, 1.0) / spread(s, 1.0), 1.2, 0.01) << s;
    EXPECT_NEAR(spread(s, 2.0) / spread(s, 1.0), 2.0, 0.02) << s;
  }
  auto bad = briefOptions(256);
  bad.supportScale = 0;
  EXPECT_THROW(DescriptorExtractor(nullptr, bad, tests), std::invalid_argument);
}

// comparisonPositions() is empty exactly for the keypoints compute() drops: near the border some of
// the (rotated) tests leave the level although every point can be placed.
TEST(Brief, TestPositionsAreEmptyExactlyWhenComputeDropsTheKeypoint) {
  const ComparisonSet tests = randomComparisons(256, 8);
  const ImagePyramid pyramid(horizontalRamp(), PyramidOptions{});
  for (const DescriptorKind kind : {DescriptorKind::Brief, DescriptorKind::MaskedBrief}) {
    auto o = briefOptions(256);
    o.kind = kind;
    const DescriptorExtractor extractor(nullptr, o, tests);
    int dropped = 0, kept = 0;
    for (float x = 2.f; x < 40.f; x += 1.f)
      for (const float angle : {0.f, 45.f}) {
        std::vector<cv::KeyPoint> one{cv::KeyPoint(x, 128.f, 31.f, angle)};
        cv::Mat descriptors;
        extractor.compute(pyramid, one, descriptors);
        const bool described = one.size() == 1;
        EXPECT_EQ(extractor.comparisonPositions(pyramid, cv::KeyPoint(x, 128.f, 31.f, angle)).empty(), !described)
            << "x " << x << " angle " << angle;
        ++(described ? kept : dropped);
      }
    EXPECT_GT(dropped, 0);
    EXPECT_GT(kept, 0);
  }
}

TEST(Brief, InvalidOptionsAreRejected) {
  const ComparisonSet tests = randomComparisons(256, 5);
  for (const int bits : {0, 16, 100, 544}) {
    auto o = briefOptions(256);
    o.bits = bits;
    EXPECT_THROW(DescriptorExtractor(nullptr, o, tests), std::invalid_argument) << bits;
  }
  auto o = briefOptions(512);
  EXPECT_THROW(DescriptorExtractor(nullptr, o, tests), std::invalid_argument);  // set too short
  o = briefOptions(256);
  o.kind = DescriptorKind::DBrief;
  EXPECT_THROW(DescriptorExtractor(nullptr, o, tests), std::invalid_argument);  // no camera
  for (const int radius : {3, 16}) {
    o = briefOptions(256);
    o.orientationRadius = radius;
    EXPECT_THROW(DescriptorExtractor(nullptr, o, tests), std::invalid_argument) << radius;
  }
}

// The BOLD-like masked BRIEF: BRIEF's bits, plus the mask of the three rotations, no camera.
TEST(MaskedBrief, IsBriefPlusTheAgreementOfThreeRotationsOnARamp) {
  const ComparisonSet tests = randomComparisons(256, 11);
  auto o = briefOptions(256);
  const DescriptorExtractor brief(nullptr, o, tests);
  o.kind = DescriptorKind::MaskedBrief;
  o.maskRotationDeg = 15.0;
  const DescriptorExtractor masked(nullptr, o, tests);
  std::vector<cv::KeyPoint> kb{cv::KeyPoint(128.f, 127.f, 31.f, 40.f, 1.f, 0)}, km = kb;
  cv::Mat db, dm, mb, mm;
  brief.compute(horizontalRamp(), kb, db, mb);
  masked.compute(horizontalRamp(), km, dm, mm);
  ASSERT_EQ(dm.rows, 1);
  EXPECT_TRUE(mb.empty());
  EXPECT_EQ(cv::norm(db, dm, cv::NORM_HAMMING), 0.0);
  ASSERT_EQ(mm.size(), dm.size());
  int checked = 0, unstable = 0;
  for (int d = 0; d < 256; ++d) {
    const ComparisonPair& t = tests.tests[d];
    double v[3];
    for (int r = 0; r < 3; ++r) {
      const double deg = 40.0 + (r == 0 ? 0.0 : r == 1 ? 15.0 : -15.0);
      v[r] = rotatedX(t.x2, t.y2, deg) - rotatedX(t.x1, t.y1, deg);
    }
    if (std::abs(v[0]) < 0.1 || std::abs(v[1]) < 0.1 || std::abs(v[2]) < 0.1) continue;
    const bool expected = (v[0] > 0) == (v[1] > 0) && (v[0] > 0) == (v[2] > 0);
    EXPECT_EQ(bit(mm, 0, d), expected) << "test " << d;
    ++checked;
    unstable += !expected;
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(unstable, 5);
}

// compute() describes the keypoints in parallel blocks: its output must not depend on how many
// threads share them. A serial run (one thread allowed) is the reference for runs on 2, 3 and 8.
TEST(Brief, ParallelExtractionIsDeterministic) {
  const ComparisonSet tests = randomComparisons(256, 6);
  cv::Mat img(480, 752, CV_8U);
  cv::randu(img, 0, 256);
  std::vector<cv::KeyPoint> kps;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(0, 752), uy(0, 480), ua(0, 360);
  for (int i = 0; i < 3000; ++i) kps.emplace_back(ux(rng), uy(rng), 31.f, ua(rng), 1.f, i % 4);
  const DescriptorExtractor brief(nullptr, briefOptions(256), tests);
  const auto describe = [&](int threads, std::vector<cv::KeyPoint>& described, cv::Mat& descriptors) {
    described = kps;
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      ASSERT_EQ(tbb::this_task_arena::max_concurrency(), threads);
      brief.compute(img, described, descriptors);
    });
  };
  std::vector<cv::KeyPoint> serialKeypoints;
  cv::Mat serial;
  describe(1, serialKeypoints, serial);
  ASSERT_GT(serialKeypoints.size(), 1500u);
  ASSERT_LT(serialKeypoints.size(), kps.size()) << "some keypoints lie too near the border to be described";
  for (const int threads : {2, 3, 8}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    std::vector<cv::KeyPoint> parallelKeypoints;
    cv::Mat parallel;
    describe(threads, parallelKeypoints, parallel);
    ASSERT_EQ(parallelKeypoints.size(), serialKeypoints.size());
    for (size_t i = 0; i < serialKeypoints.size(); ++i) {
      ASSERT_EQ(parallelKeypoints[i].pt, serialKeypoints[i].pt) << i;
      ASSERT_EQ(parallelKeypoints[i].angle, serialKeypoints[i].angle) << i;
    }
    EXPECT_EQ(cv::norm(parallel, serial, cv::NORM_HAMMING), 0.0);
  }
}

}  // namespace
}  // namespace mdbrief
