// The footprint follows the keypoint size (DescriptorOptions::supportScale): for keypoints of
// cv::ORB and of the library's modORB (size = 31 * scale of their octave) the tests land exactly
// where an octave-based placement puts them, the keypoint's octave scale times the rotated test
// offsets: the placement the library used before sizes decided.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "test_data.hpp"

using namespace mdbrief;

TEST(DescriptorSupport, OrbAndModOrbKeypointsAreDescribedWhereTheirOctavePlacesThem) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const cv::Mat img = cv::imread((*doc / "box_in_scene.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty());
  const CameraPtr cam = loadCamera((mdbrief::testing::sourceDir() / "configs/cameras/pinhole_example.yaml").string());
  cv::Mat image;
  cv::resize(img, image, cam->imageSize());
  std::vector<cv::KeyPoint> orb;
  cv::ORB::create(1000)->detect(image, orb);
  // modORB on cv::ORB's pyramid: sizes 31 * 1.2^octave.
  DetectorOptions modOrb;
  modOrb.method = DetectorMethod::ModOrb;
  modOrb.pyramid = PyramidOptions{8, 1.2, 0};
  std::vector<cv::KeyPoint> own = Detector(cam, modOrb).detect(image);
  DescriptorOptions o;
  o.kind = DescriptorKind::Brief;
  o.pattern = "brief_random_512";
  const DescriptorExtractor brief(cam, o);
  const ImagePyramid pyramid(image, modOrb.pyramid);
  const ComparisonSet& tests = brief.comparisonSet();
  for (std::vector<cv::KeyPoint>* kps : {&orb, &own}) {
    ASSERT_EQ(kps->size(), 1000u);
    int checked = 0;
    for (const cv::KeyPoint& kp : *kps) {
      const auto placed = brief.comparisonPositions(pyramid, kp);
      if (placed.empty()) continue;  // near the border
      ++checked;
      const double scale = std::pow(1.2, kp.octave), a = kp.angle * CV_PI / 180.0;
      const double c = std::cos(a) * scale, sn = std::sin(a) * scale;
      for (size_t d = 0; d < placed.size(); ++d) {
        const ComparisonPair& t = tests.tests[d];
        const cv::Point2d p1(kp.pt.x + c * t.x1 - sn * t.y1, kp.pt.y + sn * t.x1 + c * t.y1);
        const cv::Point2d p2(kp.pt.x + c * t.x2 - sn * t.y2, kp.pt.y + sn * t.x2 + c * t.y2);
        // Fixed-point positions: 1/32 of a level pixel.
        ASSERT_LT(cv::norm(cv::Point2d(placed[d].first) - p1), scale / 16) << "test " << d << " at " << kp.pt;
        ASSERT_LT(cv::norm(cv::Point2d(placed[d].second) - p2), scale / 16) << "test " << d << " at " << kp.pt;
      }
    }
    EXPECT_GT(checked, 900);
  }
}
