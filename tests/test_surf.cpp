// The project's SURF fast-Hessian detector: blob position, scale and polarity on synthetic
// images, rotation covariance of the orientation, and repeatability on graf 1 -> 3.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "patchextract/surf_detector.hpp"
#include "test_data.hpp"

using namespace mdbrief::train;

namespace {

cv::Mat blobImage(double cx, double cy, double sigma, bool bright) {
  cv::Mat img(160, 200, CV_8UC1);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const double g = std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * sigma * sigma));
      img.at<uint8_t>(y, x) = static_cast<uint8_t>(std::lround(bright ? 40 + 200 * g : 240 - 200 * g));
    }
  return img;
}

}  // namespace

TEST(Surf, FindsAGaussianBlobAtItsCentreAndScale) {
  for (const bool bright : {true, false}) {
    const auto kps = detectSurf(blobImage(100.3, 80.6, 5.0, bright));
    ASSERT_FALSE(kps.empty());
    const cv::KeyPoint& k = kps.front();
    EXPECT_NEAR(k.pt.x, 100.3, 1.0);
    EXPECT_NEAR(k.pt.y, 80.6, 1.0);
    const double s = k.size / 20.0;  // SURF scale; a Gaussian blob of sigma 5 peaks near s = 5
    EXPECT_GT(s, 3.5);
    EXPECT_LT(s, 7.5);
    EXPECT_EQ(k.class_id, bright ? 1 : 0);
    EXPECT_GE(k.angle, 0.f);
    EXPECT_LT(k.angle, 360.f);
  }
  EXPECT_THROW(detectSurf(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(detectSurf(cv::Mat(10, 10, CV_8UC3)), std::invalid_argument);
  EXPECT_TRUE(detectSurf(cv::Mat(100, 100, CV_8UC1, cv::Scalar(128))).empty());
}

TEST(Surf, OrientationFollowsARotationOfTheImage) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const cv::Mat img = cv::imread((*dir / "graf1.png").string(), cv::IMREAD_GRAYSCALE)(cv::Rect(100, 100, 400, 400)).clone();
  cv::Mat rotated;
  cv::rotate(img, rotated, cv::ROTATE_90_CLOCKWISE);  // (x, y) -> (H - 1 - y, x): +90 degrees
  SurfOptions o;
  o.maxKeypoints = 300;
  const auto a = detectSurf(img, o), b = detectSurf(rotated, o);
  int matched = 0, consistent = 0;
  for (const auto& ka : a) {
    const cv::Point2f expect(img.rows - 1 - ka.pt.y, ka.pt.x);
    for (const auto& kb : b) {
      if (cv::norm(kb.pt - expect) > 1.0 || std::abs(kb.size - ka.size) > 0.2 * ka.size) continue;
      ++matched;
      const double diff = std::fmod(kb.angle - ka.angle - 90.0 + 720.0, 360.0);
      consistent += std::min(diff, 360.0 - diff) < 15.0;
      break;
    }
  }
  ASSERT_GT(matched, 100);
  EXPECT_GT(double(consistent) / matched, 0.8) << consistent << " of " << matched;
}

TEST(Surf, RepeatableOnGraf1To3) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const cv::Mat a = cv::imread((*dir / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat b = cv::imread((*dir / "graf3.png").string(), cv::IMREAD_GRAYSCALE);
  cv::Mat H;
  cv::FileStorage fs((*dir / "H1to3p.xml").string(), cv::FileStorage::READ);
  fs.getFirstTopLevelNode() >> H;
  ASSERT_FALSE(a.empty() || b.empty() || H.empty());
  SurfOptions o;
  o.maxKeypoints = 1000;
  const auto ka = detectSurf(a, o), kb = detectSurf(b, o);
  int visible = 0, repeated = 0;
  for (const auto& k : ka) {
    std::vector<cv::Point2f> src{k.pt}, dst;
    cv::perspectiveTransform(src, dst, H);
    const cv::Point2f p = dst[0];
    if (p.x < 10 || p.y < 10 || p.x > b.cols - 10 || p.y > b.rows - 10) continue;
    ++visible;
    for (const auto& q : kb)
      if (cv::norm(q.pt - p) < 3.0) {
        ++repeated;
        break;
      }
  }
  ASSERT_GT(visible, 300);
  const double repeatability = double(repeated) / visible;
  RecordProperty("repeatability", std::to_string(repeatability));
  EXPECT_GT(repeatability, 0.3) << repeated << " of " << visible;
}
