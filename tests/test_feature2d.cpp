// mdbrief::MdBrief as a cv::Feature2D: the contract cv::ORB fulfils (sizes, types, norm,
// detect/compute/detectAndCompute agreement, FileStorage round trip, input types) and a generic
// OpenCV matching pipeline that must find correct matches on graf1 -> graf3 with both.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "scenes/photo_camera.hpp"
#include "scenes/plane_renderer.hpp"
#include "test_data.hpp"

namespace mdbrief {
namespace {

CameraPtr fisheyeCamera() {
  return loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
}

// Graffiti through the paper's fisheye camera (empty without opencv-doc).
cv::Mat fisheyeImage(const Camera& camera) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc) return {};
  PlaneScene scene;
  scene.texture = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  if (scene.texture.empty()) return {};
  scene.texelSize = 0.004;
  CameraPose pose;
  pose.centre = {0.3, 0.1, -0.8};
  return renderPlane(camera, pose, scene);
}


TEST(MdBriefFeature2D, ReportsOrbCompatibleTraits) {
  MdBriefOptions o;
  o.descriptor.bits = 512;
  const cv::Ptr<cv::Feature2D> f = MdBrief::create(fisheyeCamera(), o);
  EXPECT_EQ(f->descriptorSize(), 64);
  EXPECT_EQ(f->descriptorType(), CV_8U);
  EXPECT_EQ(f->defaultNorm(), cv::NORM_HAMMING);
  EXPECT_EQ(f->getDefaultName(), "Feature2D.MdBrief");
  EXPECT_FALSE(f->empty());
}

TEST(MdBriefFeature2D, CameraMayBeNullOnlyForBrief) {
  MdBriefOptions o;
  EXPECT_THROW(MdBrief::create(nullptr, o), std::invalid_argument);
  o.descriptor.kind = DescriptorKind::DBrief;
  EXPECT_THROW(MdBrief::create(nullptr, o), std::invalid_argument);
  o.descriptor.kind = DescriptorKind::Brief;
  EXPECT_NO_THROW(MdBrief::create(nullptr, o));
}

TEST(MdBriefFeature2D, RejectsAnUnusablePyramid) {
  MdBriefOptions o;
  o.detector.pyramid.levels = 4;
  EXPECT_NO_THROW(MdBrief::create(fisheyeCamera(), o));
  o.detector.pyramid.smoothingKernel = 4;
  EXPECT_THROW(MdBrief::create(fisheyeCamera(), o), std::invalid_argument);
}

TEST(MdBriefFeature2D, DetectThenComputeEqualsDetectAndCompute) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat image = fisheyeImage(*camera);
  if (image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const cv::Ptr<cv::Feature2D> f = MdBrief::create(camera);
  std::vector<cv::KeyPoint> a, b;
  cv::Mat da, db;
  f->detectAndCompute(image, cv::noArray(), a, da);
  f->detect(image, b);
  f->compute(image, b, db);
  ASSERT_GT(a.size(), 500u);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(da.rows, static_cast<int>(a.size()));
  EXPECT_EQ(da.cols, 32);
  EXPECT_EQ(da.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(da, db, cv::NORM_HAMMING), 0.0);
  for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].pt, b[i].pt);
}

// The level follows the size (DescriptorOptions::supportScale), so the octave a keypoint comes
// with, from another detector or none, changes nothing; an extreme one must not overflow either.
TEST(MdBriefFeature2D, GivenKeypointsAreDescribedByTheirSizeWhateverTheirOctave) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat image = fisheyeImage(*camera);
  if (image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const cv::Ptr<MdBrief> f = MdBrief::create(camera);
  std::vector<cv::KeyPoint> detected;
  cv::Mat expected;
  f->detectAndCompute(image, cv::noArray(), detected, expected);
  int above0 = 0;
  for (const auto& k : detected) above0 += k.octave > 0;
  ASSERT_GT(above0, 100);
  for (const int octave : {0, -5, std::numeric_limits<int>::max(), std::numeric_limits<int>::min()}) {
    std::vector<cv::KeyPoint> given = detected;
    for (auto& k : given) k.octave = octave;
    cv::Mat d;
    f->compute(image, given, d);
    ASSERT_EQ(given.size(), detected.size()) << "octave " << octave;
    EXPECT_EQ(cv::norm(d, expected, cv::NORM_HAMMING), 0.0) << "octave " << octave;
  }
}

TEST(MdBriefFeature2D, MasksOnlyForMdBriefAndAlignedWithKeypoints) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat image = fisheyeImage(*camera);
  if (image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const cv::Ptr<MdBrief> md = MdBrief::create(camera);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc, masks;
  md->detectAndComputeWithMasks(image, cv::noArray(), kps, desc, masks);
  ASSERT_FALSE(kps.empty());
  EXPECT_EQ(masks.size(), desc.size());
  EXPECT_EQ(desc.rows, static_cast<int>(kps.size()));
  // The mask marks stable tests: neither all nor none on a textured image.
  const int allStableBytes = cv::countNonZero(masks == 255);
  EXPECT_GT(cv::countNonZero(masks), 0);
  EXPECT_LT(allStableBytes, static_cast<int>(masks.total()));

  MdBriefOptions o;
  o.descriptor.kind = DescriptorKind::DBrief;
  const cv::Ptr<MdBrief> d = MdBrief::create(camera, o);
  cv::Mat dmasks = cv::Mat::ones(3, 3, CV_8U);
  d->detectAndComputeWithMasks(image, cv::noArray(), kps, desc, dmasks);
  EXPECT_TRUE(dmasks.empty());
}

TEST(MdBriefFeature2D, UpsampledFirstLevelKeepsKeypointsInInputPixels) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat image = fisheyeImage(*camera);
  if (image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  // modORB (on cv::ORB's pyramid) finds keypoints on the enlarged level itself; the Hessian, whose
  // maxima need a finer level, on the input level above it.
  MdBriefOptions modOrb;
  modOrb.detector.method = DetectorMethod::ModOrb;
  modOrb.detector.pyramid = PyramidOptions{};
  MdBriefOptions hessian;
  hessian.detector.method = DetectorMethod::Hessian;
  for (auto [o, finest] : {std::pair{modOrb, 0}, std::pair{hessian, 1}}) {
    SCOPED_TRACE(toString(o.detector.method));
    o.detector.pyramid.firstLevel = 1;
    std::vector<cv::KeyPoint> kps;
    cv::Mat desc;
    MdBrief::create(camera, o)->detectAndCompute(image, cv::noArray(), kps, desc);
    ASSERT_GT(kps.size(), 500u);
    EXPECT_EQ(desc.rows, static_cast<int>(kps.size()));
    bool anyFinest = false;
    for (const auto& kp : kps) {
      EXPECT_TRUE(camera->isValid(kp.pt)) << kp.pt;
      EXPECT_GE(kp.octave, finest);
      anyFinest |= kp.octave == finest;
    }
    EXPECT_TRUE(anyFinest);
  }
}

TEST(MdBriefFeature2D, AcceptsGreyBgrAndBgraAlike) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat grey = fisheyeImage(*camera);
  if (grey.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  cv::Mat bgr, bgra;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  const cv::Ptr<cv::Feature2D> f = MdBrief::create(camera);
  std::vector<cv::KeyPoint> k1, k3, k4;
  cv::Mat d1, d3, d4;
  f->detectAndCompute(grey, cv::noArray(), k1, d1);
  f->detectAndCompute(bgr, cv::noArray(), k3, d3);
  f->detectAndCompute(bgra, cv::noArray(), k4, d4);
  ASSERT_EQ(k1.size(), k3.size());
  ASSERT_EQ(k1.size(), k4.size());
  EXPECT_EQ(cv::norm(d1, d3, cv::NORM_HAMMING), 0.0);
  EXPECT_EQ(cv::norm(d1, d4, cv::NORM_HAMMING), 0.0);
}

TEST(MdBriefFeature2D, RejectsBadInput) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Ptr<cv::Feature2D> f = MdBrief::create(camera);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  EXPECT_THROW(f->detectAndCompute(cv::Mat(), cv::noArray(), kps, desc), std::invalid_argument);
  EXPECT_THROW(f->detectAndCompute(cv::Mat(camera->imageSize(), CV_32F, cv::Scalar(0)), cv::noArray(), kps, desc),
               std::invalid_argument);
  EXPECT_THROW(f->detectAndCompute(cv::Mat(cv::Size(100, 100), CV_8U, cv::Scalar(0)), cv::noArray(), kps, desc),
               std::invalid_argument);
  // A mask of the wrong size.
  EXPECT_THROW(f->detectAndCompute(cv::Mat(camera->imageSize(), CV_8U, cv::Scalar(0)), cv::Mat(10, 10, CV_8U), kps,
                                   desc),
               std::invalid_argument);
}

TEST(MdBriefFeature2D, ExplicitMaskRestrictsKeypoints) {
  const CameraPtr camera = fisheyeCamera();
  const cv::Mat image = fisheyeImage(*camera);
  if (image.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  cv::Mat mask(image.size(), CV_8U, cv::Scalar(0));
  mask.colRange(0, image.cols / 2).setTo(255);
  std::vector<cv::KeyPoint> kps;
  MdBrief::create(camera)->detect(image, kps, mask);
  ASSERT_FALSE(kps.empty());
  for (const auto& kp : kps) EXPECT_LT(kp.pt.x, image.cols / 2.f);
}

// Every option of a and b alike (the whole table, so an option added later is compared too).
::testing::AssertionResult sameOptions(const MdBriefOptions& a, const MdBriefOptions& b) {
  for (const auto& field : mdBriefOptionFields())
    if (field.get(a) != field.get(b))
      return ::testing::AssertionFailure()
             << field.member << ": " << fieldValueText(field.get(a)) << " vs " << fieldValueText(field.get(b));
  return ::testing::AssertionSuccess();
}

TEST(MdBriefFeature2D, FileStorageRoundTripKeepsEveryOption) {
  MdBriefOptions o;
  PyramidOptions& p = o.detector.pyramid;
  p.levels = 5;
  p.scaleFactor = 1.3;
  p.firstLevel = 2;
  p.smoothingKernel = 5;
  p.smoothingSigma = 1.5;
  o.detector.nfeatures = 321;
  o.detector.method = DetectorMethod::ModOrb;
  o.detector.hessianSigma = 1.7;
  o.detector.hessianThreshold = 2e-4;
  o.detector.hessianScaleExponent = 0.5;
  o.detector.relocalise = false;
  o.detector.corners = CornerDetector::Agast;
  o.detector.threshold = 17;
  o.detector.fallbackThreshold = 5;
  o.detector.harrisBlockSize = 5;
  o.detector.harrisK = 0.05;
  o.detector.spread = true;
  o.detector.orientationRadius = 12;
  o.detector.patchSize = 27;
  o.detector.borderMargin = 30;
  o.detector.conformal = true;
  o.descriptor.kind = DescriptorKind::DBrief;
  o.descriptor.bits = 128;
  o.descriptor.pattern = builtinComparisonSetNames().back();  // any non-empty name survives the trip
  o.descriptor.useOrientation = false;
  o.descriptor.orientation = OrientationSource::Keypoint;
  o.descriptor.orientationRadius = 9;
  o.descriptor.form = DistortionForm::Paper;
  o.descriptor.sampling = Sampling::Nearest;
  o.descriptor.maskRotationDeg = 7.5;
  o.descriptor.maxIncidenceDeg = 70.0;
  o.descriptor.supportScale = 2.5;
  const CameraPtr camera = fisheyeCamera();
  // Every option differs from the defaults the reading object starts from, so that each one
  // is seen to be read back.
  for (const auto& field : mdBriefOptionFields())
    EXPECT_NE(field.get(o), field.get(MdBriefOptions{})) << field.member << " is its default";

  for (const char* ext : {".yml", ".json", ".xml"}) {
    cv::FileStorage out(ext, cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    MdBrief::create(camera, o)->write(out);
    const std::string text = out.releaseAndGetString();
    const cv::Ptr<MdBrief> back = MdBrief::create(camera);
    cv::FileStorage in(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    back->read(in.root());
    const MdBriefOptions& r = back->options();
    SCOPED_TRACE(ext);
    EXPECT_EQ(r.detector.pyramid.levels, 5);
    EXPECT_DOUBLE_EQ(r.detector.pyramid.scaleFactor, 1.3);
    EXPECT_EQ(r.detector.pyramid.firstLevel, 2);
    EXPECT_EQ(r.detector.pyramid.smoothingKernel, 5);
    EXPECT_DOUBLE_EQ(r.detector.pyramid.smoothingSigma, 1.5);
    EXPECT_EQ(r.detector.nfeatures, 321);
    EXPECT_EQ(r.detector.method, DetectorMethod::ModOrb);
    EXPECT_DOUBLE_EQ(r.detector.hessianSigma, 1.7);
    EXPECT_DOUBLE_EQ(r.detector.hessianThreshold, 2e-4);
    EXPECT_DOUBLE_EQ(r.detector.hessianScaleExponent, 0.5);
    EXPECT_FALSE(r.detector.relocalise);
    EXPECT_EQ(r.detector.corners, CornerDetector::Agast);
    EXPECT_EQ(r.detector.threshold, 17);
    EXPECT_EQ(r.detector.fallbackThreshold, 5);
    EXPECT_EQ(r.detector.harrisBlockSize, 5);
    EXPECT_DOUBLE_EQ(r.detector.harrisK, 0.05);
    EXPECT_TRUE(r.detector.spread);
    EXPECT_EQ(r.detector.orientationRadius, 12);
    EXPECT_EQ(r.detector.patchSize, 27);
    EXPECT_EQ(r.detector.borderMargin, 30);
    EXPECT_TRUE(r.detector.conformal);
    EXPECT_EQ(r.descriptor.kind, DescriptorKind::DBrief);
    EXPECT_EQ(r.descriptor.bits, 128);
    EXPECT_EQ(r.descriptor.pattern, o.descriptor.pattern);
    EXPECT_FALSE(r.descriptor.useOrientation);
    EXPECT_EQ(r.descriptor.orientation, OrientationSource::Keypoint);
    EXPECT_EQ(r.descriptor.orientationRadius, 9);
    EXPECT_EQ(r.descriptor.form, DistortionForm::Paper);
    EXPECT_EQ(r.descriptor.sampling, Sampling::Nearest);
    EXPECT_DOUBLE_EQ(r.descriptor.maskRotationDeg, 7.5);
    EXPECT_DOUBLE_EQ(r.descriptor.maxIncidenceDeg, 70.0);
    EXPECT_DOUBLE_EQ(r.descriptor.supportScale, 2.5);
    EXPECT_EQ(back->descriptorSize(), 16);
    EXPECT_TRUE(sameOptions(r, o));
  }
}

TEST(MdBriefFeature2D, ReadRejectsBadValuesAndKeepsTheOldOptions) {
  // Not the defaults, so that a read falling back to them would show.
  MdBriefOptions old;
  old.detector.method = DetectorMethod::ModOrb;
  old.detector.pyramid = PyramidOptions{};
  old.descriptor.bits = 128;
  ASSERT_FALSE(sameOptions(old, MdBriefOptions{}));
  const cv::Ptr<MdBrief> f = MdBrief::create(fisheyeCamera(), old);
  const std::string bad = "%YAML:1.0\n---\nname: Feature2D.MdBrief\ndescriptor:\n  kind: surf\n";
  cv::FileStorage in(bad, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  EXPECT_THROW(f->read(in.root()), std::invalid_argument);
  const std::string badBits = "%YAML:1.0\n---\ndescriptor:\n  bits: 100\n";
  cv::FileStorage in2(badBits, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  EXPECT_THROW(f->read(in2.root()), std::invalid_argument);
  EXPECT_TRUE(sameOptions(f->options(), old));
  EXPECT_EQ(f->descriptorSize(), 16);
  const std::string method = "%YAML:1.0\n---\ndetector:\n  method: harris\n";
  cv::FileStorage in4(method, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  try {
    f->read(in4.root());
    ADD_FAILURE() << "an unknown detector method was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hessian"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(sameOptions(f->options(), old));
  const std::string orb = "%YAML:1.0\n---\nname: Feature2D.ORB\n";
  cv::FileStorage in3(orb, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  EXPECT_THROW(f->read(in3.root()), std::invalid_argument);
  EXPECT_TRUE(sameOptions(f->options(), old));
}

// A pipeline written only against cv::Feature2D, as user code would be: detect and describe
// both images, match with BFMatcher(defaultNorm) and Lowe's ratio test, and count the matches
// the ground-truth homography confirms within 3 px.
int inlierMatches(const cv::Ptr<cv::Feature2D>& feature, const cv::Mat& a, const cv::Mat& b, const cv::Matx33d& H) {
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  feature->detectAndCompute(a, cv::noArray(), ka, da);
  feature->detectAndCompute(b, cv::noArray(), kb, db);
  cv::BFMatcher matcher(feature->defaultNorm());
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(da, db, knn, 2);
  int inliers = 0;
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance >= 0.8f * m[1].distance) continue;
    const cv::Point2f p = ka[m[0].queryIdx].pt;
    const cv::Vec3d q = H * cv::Vec3d(p.x, p.y, 1.0);
    const cv::Point2d projected(q[0] / q[2], q[1] / q[2]);
    if (cv::norm(projected - cv::Point2d(kb[m[0].trainIdx].pt)) < 3.0) ++inliers;
  }
  return inliers;
}

TEST(MdBriefFeature2D, GenericOpenCvPipelineMatchesGraf1To3LikeOrb) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc data not installed");
  const cv::Mat a = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_COLOR);
  const cv::Mat b = cv::imread((*doc / "graf3.png").string(), cv::IMREAD_COLOR);
  cv::FileStorage hs((*doc / "H1to3p.xml").string(), cv::FileStorage::READ);
  cv::Mat Hm;
  hs.getFirstTopLevelNode() >> Hm;
  if (a.empty() || b.empty() || Hm.empty()) MDBRIEF_SKIP_WITHOUT_DATA("graf1/graf3/H1to3p.xml missing");
  const cv::Matx33d H(Hm);

  const int orb = inlierMatches(cv::ORB::create(1000), a, b, H);
  const int md = inlierMatches(MdBrief::create(photoCamera(a.size())), a, b, H);
  MdBriefOptions briefOptions;
  briefOptions.descriptor.kind = DescriptorKind::Brief;
  const int brief = inlierMatches(MdBrief::create(nullptr, briefOptions), a, b, H);
  std::printf("graf1->3 inliers: ORB %d, mdBRIEF (pinhole) %d, BRIEF %d\n", orb, md, brief);
  // Measured: ORB 103, mdBRIEF 132, BRIEF 124. Ours are the same on every CPU and SIMD level:
  // floors about 8 % below them. cv::ORB's own, which OpenCV's kernels may move, 15 % below.
  EXPECT_GE(orb, 88);
  EXPECT_GE(md, 121);
  EXPECT_GE(brief, 114);
  // The defaults, a binary descriptor as ORB's, find more than ORB does.
  EXPECT_GT(md, orb);
}

}  // namespace
}  // namespace mdbrief
