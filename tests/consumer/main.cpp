// Detect, describe (mdBRIEF with the default compiled-in pattern) and match a synthetic image
// against a shifted copy; exit 0 when most keypoints find their shifted partner. With an
// argument, also load that calibration file (an installed example camera). Then the two-view fits
// on the matches. One include, the umbrella header, brings the whole public API.
#include <cstdio>
#include <memory>
#include <vector>

#include <mdbrief/mdbrief.hpp>
#include <opencv2/imgproc.hpp>

int main(int argc, char** argv) {
  if (argc > 1) {
    const auto installed = mdbrief::loadCamera(argv[1]);
    std::printf("%s: %s %dx%d\n", argv[1], installed->modelName().c_str(), installed->imageSize().width,
                installed->imageSize().height);
  }
  cv::Mat image(480, 640, CV_8U);
  cv::randu(image, 0, 256);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 2.0);
  const cv::Mat shifted = image(cv::Rect(5, 3, 600, 440)).clone(), original = image(cv::Rect(0, 0, 600, 440));

  mdbrief::CameraIntrinsics k;
  k.width = 600, k.height = 440, k.fx = k.fy = 400, k.cx = 300, k.cy = 220;
  const auto camera = std::make_shared<mdbrief::PinholeCamera>(k);
  const mdbrief::Detector detector(camera);
  const mdbrief::DescriptorExtractor extractor(camera);

  auto k1 = detector.detect(original), k2 = detector.detect(shifted);
  cv::Mat d1, d2, m1, m2;
  extractor.compute(original, k1, d1, m1);
  extractor.compute(shifted, k2, d2, m2);
  const auto matches = mdbrief::matchBruteForceMasked(d1, m1, d2, m2, mdbrief::MatchOptions{});
  int correct = 0;
  for (const auto& m : matches) {
    const cv::Point2f d = k1[m.queryIdx].pt - k2[m.trainIdx].pt - cv::Point2f(5, 3);
    correct += d.dot(d) < 4.f;
  }
  std::printf("pattern %s: %zu keypoints, %d of %zu matches correct\n", mdbrief::defaultComparisonSetName().c_str(),
              k1.size(), correct, matches.size());
  // The two-view fits on the matches' bearings (a static library brings OpenGV to the link).
  std::vector<cv::Vec3d> a, b;
  for (const auto& m : matches) {
    cv::Vec3d ba, bb;
    if (camera->pixelToBearing(k1[m.queryIdx].pt, ba) && camera->pixelToBearing(k2[m.trainIdx].pt, bb))
      a.push_back(ba), b.push_back(bb);
  }
  const auto plane = mdbrief::fitHomography(a, b);
  const auto general = mdbrief::fitEssential(a, b);
  std::printf("homography: %d inliers; essential: %s\n", plane.inlierCount,
              general.ok() ? "a pose" : general.reason.c_str());
  return k1.size() > 100 && correct > 0.5 * static_cast<double>(matches.size()) && plane.inlierCount >= correct / 2
             ? 0
             : 1;
}
