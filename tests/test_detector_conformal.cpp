// DetectorOptions::conformal: detection on the camera's stereographic view, keypoints mapped
// back through the camera model: on a photo seen through the LaFiDa fisheye calibration, and
// through a narrow pinhole, where the view is nearly the image itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/pinhole.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "test_data.hpp"

namespace {

using mdbrief::Detector;
using mdbrief::DetectorMethod;
using mdbrief::DetectorOptions;

mdbrief::CameraPtr fisheye() {
  return mdbrief::loadCamera((mdbrief::testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
}

// An opencv-doc photo at the calibration's size, treated as what the fisheye lens sees.
cv::Mat scene(const mdbrief::Camera& camera) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir) return {};
  const cv::Mat photo = cv::imread((*dir / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  if (photo.empty()) return {};
  cv::Mat out;
  cv::resize(photo, out, camera.imageSize(), 0, 0, cv::INTER_AREA);
  return out;
}

#define REQUIRE_IMAGE(image) \
  if ((image).empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc's graf1.png not found")

TEST(ConformalDetection, KeypointsKeepTheBudgetTheValidAreaTheMaskAndRepeat) {
  const mdbrief::CameraPtr camera = fisheye();
  const cv::Mat image = scene(*camera);
  REQUIRE_IMAGE(image);
  const cv::Mat valid = mdbrief::validAreaMask(*camera, camera->imageSize());
  for (const auto method : {DetectorMethod::ModOrb, DetectorMethod::Hessian}) {
    SCOPED_TRACE(static_cast<int>(method));
    DetectorOptions options;
    options.method = method;
    options.nfeatures = 500;
    options.conformal = true;
    const Detector detector(camera, options);
    const std::vector<cv::KeyPoint> keypoints = detector.detect(image);
    // A quarter more are detected on the view, so losses on the way back do not eat the budget.
    EXPECT_EQ(keypoints.size(), 500u);
    for (const cv::KeyPoint& k : keypoints) {
      ASSERT_TRUE(camera->isValid(k.pt));
      EXPECT_GT(k.size, 0.f);
      EXPECT_GE(k.octave, 0);
      EXPECT_LT(k.octave, options.pyramid.levels);
      EXPECT_GE(k.angle, 0.f);
    }
    EXPECT_TRUE(std::is_sorted(keypoints.begin(), keypoints.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
      return a.response > b.response;
    }));
    // Deterministic.
    const std::vector<cv::KeyPoint> again = detector.detect(image.clone());
    ASSERT_EQ(again.size(), keypoints.size());
    for (size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].pt, keypoints[i].pt);
    // The mask is tested at the camera pixel.
    cv::Mat left = cv::Mat::zeros(image.size(), CV_8U);
    left.colRange(0, image.cols / 2).setTo(255);
    for (const cv::KeyPoint& k : detector.detect(image, left)) EXPECT_LT(k.pt.x, image.cols / 2 + 0.5f);
    // Every keypoint can be described.
    mdbrief::MdBriefOptions both;
    both.detector = options;
    std::vector<cv::KeyPoint> described;
    cv::Mat descriptors;
    mdbrief::MdBrief::create(camera, both)->detectAndCompute(image, cv::noArray(), described, descriptors);
    EXPECT_GE(described.size(), 450u);
  }
}

// Through a narrow perspective lens the stereographic view is nearly the image itself
// (r = 2 f tan(theta / 2) against f tan(theta): under 0.3 px apart at 7 degrees off axis), so the
// keypoints mapped back must land where plain detection finds them, with their sizes.
TEST(ConformalDetection, ANarrowPinholeGivesThePlainKeypoints) {
  mdbrief::CameraIntrinsics k;
  k.width = 754, k.height = 480, k.fx = k.fy = 3000.0, k.cx = 376.5, k.cy = 239.5;
  const mdbrief::CameraPtr camera = std::make_shared<mdbrief::PinholeCamera>(k);
  const cv::Mat image = scene(*camera);
  REQUIRE_IMAGE(image);
  for (const auto method : {DetectorMethod::ModOrb, DetectorMethod::Hessian}) {
    SCOPED_TRACE(static_cast<int>(method));
    DetectorOptions options;
    options.method = method;
    options.nfeatures = 300;
    const std::vector<cv::KeyPoint> plain = Detector(camera, options).detect(image);
    options.conformal = true;
    const std::vector<cv::KeyPoint> conformal = Detector(camera, options).detect(image);
    ASSERT_EQ(conformal.size(), plain.size());
    // Resampling the view moves responses a little, so not every keypoint survives; those that
    // do must sit on their plain counterpart with its size.
    std::vector<double> offsets, sizeErrors;
    for (const cv::KeyPoint& c : conformal) {
      // Within 2 px, the plain keypoint of the nearest size (corners repeat across levels).
      double best = INFINITY, at = 0;
      for (const cv::KeyPoint& p : plain) {
        const double d = std::hypot(p.pt.x - c.pt.x, p.pt.y - c.pt.y), e = std::abs(std::log(p.size / c.size));
        if (d <= 2.0 && e < best) best = e, at = d;
      }
      if (!std::isfinite(best)) continue;
      offsets.push_back(at);
      sizeErrors.push_back(best);
    }
    const auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    const int matched = static_cast<int>(offsets.size());
    ASSERT_GT(matched, 0);
    std::printf("%d of %zu within 2 px, median offset %.3f px, median |log size ratio| %.4f\n", matched,
                conformal.size(), median(offsets), median(sizeErrors));
    EXPECT_GT(matched, static_cast<int>(0.7 * conformal.size()));
    EXPECT_LT(median(offsets), 1.0);
    EXPECT_LT(median(sizeErrors), 0.05);
  }
}

}  // namespace
