// The user guide's C++ walk-through (docs/guide/README.md): load a calibration, extract features,
// match them brute force and guided, verify the matches, and start from a preset. The guide
// shows the parts between the "[guide:NAME]" and "[guide]" lines; ctest `guide_first_steps`
// runs the whole, so the guide's code compiles and does what it says.
// Usage: guide_first_steps CALIBRATION   (e.g. configs/cameras/lafida_fisheye0.yaml)
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "synthetic_scene.hpp"

// [guide:includes]
#include <mdbrief/mdbrief.hpp>  // everything; or mdbrief/camera/io.hpp, mdbrief/api/feature2d.hpp, ...
// [guide]

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "guide_first_steps: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 2) return fail("usage: guide_first_steps CALIBRATION");
  const std::string calibrationPath = argv[1];

  // [guide:load-camera]
  // Any supported calibration file: the project's YAML, OCamCalib's calib_results.txt, Kalibr,
  // basalt, OpenCV FileStorage, ... (the format is recognised; CameraFileOptions picks one).
  std::shared_ptr<mdbrief::Camera> camera = mdbrief::loadCamera(calibrationPath);
  cv::Vec3d bearing;
  camera->pixelToBearing(cv::Point2d(100, 200), bearing);  // unit ray of a pixel
  // [guide]

  // Two views: a textured image at the camera's size, and the lens rolled by 12 degrees about
  // its axis (an exact image rotation about the principal point, the pixel of the axis).
  cv::Point2d centre;
  camera->bearingToPixel(cv::Vec3d(0, 0, 1), centre);
  const cv::Mat image1 = guide::texturedImage(camera->imageSize());
  cv::Matx23d truth;
  const cv::Mat image2 = guide::rolled(image1, cv::Point2f(centre), 12.0, truth);

  // [guide:extract]
  // The defaults (the `tracking` preset): Hessian blobs, mdBRIEF-256 with its learned test set.
  cv::Ptr<mdbrief::MdBrief> features = mdbrief::MdBrief::create(camera);
  std::vector<cv::KeyPoint> keypoints1, keypoints2;
  cv::Mat descriptors1, descriptors2, masks1, masks2;  // N x 32 bytes each
  features->detectAndComputeWithMasks(image1, cv::noArray(), keypoints1, descriptors1, masks1);
  features->detectAndComputeWithMasks(image2, cv::noArray(), keypoints2, descriptors2, masks2);
  // [guide]

  // [guide:match]
  // Masked Hamming distance, mutual nearest neighbours, Lowe's ratio test at 0.55 (MatchOptions{}).
  std::vector<cv::DMatch> matches = mdbrief::matchBruteForceMasked(descriptors1, masks1, descriptors2, masks2);
  // [guide]

  // [guide:verify]
  // Keep the matches one model explains. Here the second view is an image rotation, so a
  // homography between the pixels is exact; between two poses of a moving fisheye camera fit the
  // model on the bearings instead (see "Geometry").
  std::vector<cv::Point2f> points1, points2;
  for (const cv::DMatch& m : matches) {
    points1.push_back(keypoints1[m.queryIdx].pt);
    points2.push_back(keypoints2[m.trainIdx].pt);
  }
  std::vector<unsigned char> inlier;
  const cv::Mat homography = cv::findHomography(points1, points2, cv::RANSAC, 2.0, inlier);
  // [guide]
  if (homography.empty()) return fail("no homography");

  int correct = 0, inliers = 0;
  for (size_t i = 0; i < matches.size(); ++i) {
    const cv::Point2f p = points1[i];
    const cv::Point2f expected(static_cast<float>(truth(0, 0) * p.x + truth(0, 1) * p.y + truth(0, 2)),
                               static_cast<float>(truth(1, 0) * p.x + truth(1, 1) * p.y + truth(1, 2)));
    correct += cv::norm(points2[i] - expected) <= 3.0;
    inliers += inlier[i] != 0;
  }
  std::printf("%zu and %zu keypoints, %zu matches, %d correct within 3 px, %d homography inliers\n",
              keypoints1.size(), keypoints2.size(), matches.size(), correct, inliers);
  if (matches.size() < 100) return fail("fewer than 100 matches");
  if (correct < 0.9 * static_cast<double>(matches.size())) return fail("fewer than 90 % of the matches correct");
  if (inliers < correct * 0.9) return fail("the homography keeps fewer than 90 % of the correct matches");

  // [guide:guided]
  // A tracker's next frame: each query is searched only near where the motion model puts it
  // (GuidedMatchOptions: radius 15 px by default). Here the prediction is the true motion.
  std::vector<cv::Point2f> predicted;
  for (const cv::KeyPoint& k : keypoints1) {
    predicted.emplace_back(static_cast<float>(truth(0, 0) * k.pt.x + truth(0, 1) * k.pt.y + truth(0, 2)),
                           static_cast<float>(truth(1, 0) * k.pt.x + truth(1, 1) * k.pt.y + truth(1, 2)));
  }
  std::vector<cv::DMatch> tracked = mdbrief::matchGuidedMasked(descriptors1, masks1, keypoints1, predicted,
                                                               descriptors2, masks2, keypoints2, image2.size());
  // [guide]
  std::printf("%zu guided matches\n", tracked.size());
  if (tracked.size() < matches.size()) return fail("guided matching found fewer matches than brute force");

  // [guide:geometry]
  // The check on bearings, which holds for any lens and beyond 90 degrees of incidence. A turned
  // camera (as here) or a plane: a homography between bearings. A camera that also moved, in a
  // general scene: mdbrief::fitEssential(bearings1, bearings2), whose result.pose is view 2's pose
  // in view 1 (X_1 = R X_2 + t, |t| = 1). A calibrated pair or odometry: mdbrief::checkKnownPose.
  std::vector<cv::Vec3d> bearings1, bearings2;
  for (const cv::DMatch& m : matches) {
    cv::Vec3d a, b;  // detected keypoints lie where the lens has rays
    camera->pixelToBearing(keypoints1[m.queryIdx].pt, a);
    camera->pixelToBearing(keypoints2[m.trainIdx].pt, b);
    bearings1.push_back(a), bearings2.push_back(b);
  }
  const mdbrief::HomographyResult turn = mdbrief::fitHomography(bearings1, bearings2);  // 0.005 rad
  if (!turn.ok()) std::printf("no model: %s\n", turn.reason.c_str());  // e.g. "too few matches"
  // turn.inliers[k]: match k agrees; turn.residuals[k]: its angle (radians); turn.homography
  // [guide]
  std::printf("homography on bearings: %d of %zu matches\n", turn.inlierCount, matches.size());
  if (!turn.ok() || turn.inlierCount < 0.9 * correct) return fail("the bearing homography keeps fewer than 90 % of the correct matches");

  // [guide:presets]
  // Start from another preset and change single options; validate() names a bad value.
  mdbrief::PresetSettings wide = mdbrief::presetSettings(mdbrief::Preset::Matching);  // 512 bits
  wide.features.detector.nfeatures = 1500;
  wide.matching.ratio = 0.7;
  mdbrief::validate(wide.features);
  cv::Ptr<mdbrief::MdBrief> wideFeatures = mdbrief::MdBrief::create(camera, wide.features);
  // ... then mdbrief::matchBruteForceMasked(d1, m1, d2, m2, wide.matching)
  // [guide]
  std::vector<cv::KeyPoint> wideKeypoints;
  cv::Mat wideDescriptors, wideMasks;
  wideFeatures->detectAndComputeWithMasks(image1, cv::noArray(), wideKeypoints, wideDescriptors, wideMasks);
  if (wideDescriptors.cols != 64) return fail("the matching preset does not give 512 bits");
  std::printf("matching preset: %zu keypoints of %d bytes\n", wideKeypoints.size(), wideDescriptors.cols);
  return 0;
} catch (const std::exception& e) {
  return fail(e.what());
}
