// The footprint follows the keypoint size (DescriptorOptions::supportScale): for keypoints of
// cv::ORB and of the library's detector (size = 31 * scale of their octave) BRIEF's descriptors
// are exactly those of the octave-based placement the library used before. The digests below
// were computed with that earlier library (commit 4894ad6) on the same input; they depend on
// OpenCV's ORB detector and image decoder (Debian 12's OpenCV 4.6). dBRIEF and mdBRIEF choose
// their level and footprint by the same code; their placement has since moved to the plane
// tangent at the keypoint (mdbrief/tangent_plane.hpp), so that library's digests of them no
// longer apply.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/camera_io.hpp"
#include "mdbrief/descriptor.hpp"
#include "mdbrief/detector.hpp"
#include "test_data.hpp"

using namespace mdbrief;

namespace {

std::string digest(const cv::Mat& d, const cv::Mat& m) {
  unsigned long long h = 1469598103934665603ull;
  for (const cv::Mat* a : {&d, &m})
    for (int i = 0; i < a->rows; ++i)
      for (int j = 0; j < a->cols; ++j) {
        h ^= a->at<uchar>(i, j);
        h *= 1099511628211ull;
      }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", h);
  return buf;
}

}  // namespace

TEST(DescriptorSupport, OrbAndModOrbKeypointsGiveTheOctaveBasedDescriptorsBitForBit) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc) GTEST_SKIP() << "opencv-doc not installed";
  const cv::Mat img = cv::imread((*doc / "box_in_scene.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty());
  const CameraPtr cam = loadCamera((mdbrief::testing::sourceDir() / "configs/cameras/pinhole_example.yaml").string());
  cv::Mat image;
  cv::resize(img, image, cam->imageSize());
  std::vector<cv::KeyPoint> orb;
  cv::ORB::create(1000)->detect(image, orb);
  // modORB on cv::ORB's pyramid, the one the digests were computed with.
  DetectorOptions modOrb;
  modOrb.method = DetectorMethod::ModOrb;
  modOrb.pyramid = PyramidOptions{8, 1.2, 0};
  const std::vector<cv::KeyPoint> own = Detector(cam, modOrb).detect(image);
  // keypoints -> digest of BRIEF's descriptors (brief_random_512, 256 bits)
  const char* expected[2] = {"075eebb2b3b266d2", "395ebc9cc15b61d1"};
  for (int s = 0; s < 2; ++s) {
    DescriptorOptions o;
    o.kind = DescriptorKind::Brief;
    o.pattern = "brief_random_512";
    auto kps = s == 0 ? orb : own;
    cv::Mat d, m;
    DescriptorExtractor(cam, o).compute(image, kps, d, m, modOrb.pyramid);
    EXPECT_EQ(kps.size(), 1000u);
    EXPECT_EQ(digest(d, m), expected[s]) << (s == 0 ? "cv::ORB" : "modORB");
  }
}
