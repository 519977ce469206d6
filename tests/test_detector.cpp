#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "test_data.hpp"
#include "toolkit/homography_file.hpp"
#include "toolkit/image_file.hpp"

namespace {

using mdbrief::Detector;
using mdbrief::DetectorOptions;
namespace fs = std::filesystem;

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<no std::invalid_argument>";
}

cv::Mat loadGrey(const fs::path& path) { return mdbrief::decodeGreyImage(path); }

// graf1.png from opencv-doc: a textured 800x640 photograph.
cv::Mat textured() {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir) return {};
  return loadGrey(*dir / "graf1.png");
}

#define REQUIRE_IMAGE(image) \
  if ((image).empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc's graf1.png not found")

// A fisheye-like camera whose valid area is a disc: enough for the detector, which only
// asks isValid() and imageSize().
class DiscCamera : public mdbrief::Camera {
 public:
  DiscCamera(cv::Size size, cv::Point2d centre, double radius)
      : size_(size), centre_(centre), radius_(radius) {}
  std::string modelName() const override { return "disc"; }
  cv::Size imageSize() const override { return size_; }
  bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const override {
    if (!isValid(pixel)) return false;
    // Equidistant: angle from the axis proportional to the distance from the centre.
    const cv::Point2d d = pixel - centre_;
    const double r = std::hypot(d.x, d.y), theta = r / radius_ * CV_PI / 2;
    bearing = r == 0 ? cv::Vec3d(0, 0, 1)
                     : cv::Vec3d(std::sin(theta) * d.x / r, std::sin(theta) * d.y / r, std::cos(theta));
    return true;
  }
  bool isValid(const cv::Point2d& pixel) const override {
    return pixel.x >= 0 && pixel.y >= 0 && pixel.x <= size_.width - 1 && pixel.y <= size_.height - 1 &&
           std::hypot(pixel.x - centre_.x, pixel.y - centre_.y) <= radius_;
  }
  double tangentPlaneScale() const override { return radius_ / (CV_PI / 2); }
  std::shared_ptr<Camera> resized(cv::Size newSize) const override {
    const double sx = static_cast<double>(newSize.width) / size_.width;
    return std::make_shared<DiscCamera>(newSize, centre_ * sx, radius_ * sx);
  }

 private:
  bool projectRay(const cv::Vec3d& bearing, cv::Point2d& pixel) const override {
    const double n = cv::norm(bearing);
    if (n == 0) return false;
    const double theta = std::acos(bearing[2] / n), rxy = std::hypot(bearing[0], bearing[1]);
    const double r = theta / (CV_PI / 2) * radius_;
    pixel = rxy == 0 ? centre_ : centre_ + cv::Point2d(bearing[0] / rxy * r, bearing[1] / rxy * r);
    return true;
  }
  // The detector never projects a ray.
  bool projectRayJacobian(const cv::Vec3d&, cv::Point2d&, cv::Matx23d&) const override { return false; }

  cv::Size size_;
  cv::Point2d centre_;
  double radius_;
};

bool identical(const std::vector<cv::KeyPoint>& a, const std::vector<cv::KeyPoint>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].pt != b[i].pt || a[i].size != b[i].size || a[i].angle != b[i].angle ||
        a[i].response != b[i].response || a[i].octave != b[i].octave)
      return false;
  }
  return true;
}

// modORB on cv::ORB's pyramid (8 levels of 1.2 from the input image), set explicitly: the
// tests of ORB's detection scheme describe it, whatever the library's defaults are.
DetectorOptions modOrbOptions() {
  DetectorOptions o;
  o.method = mdbrief::DetectorMethod::ModOrb;
  o.pyramid.levels = 8;
  o.pyramid.scaleFactor = 1.2;
  o.pyramid.firstLevel = 0;
  return o;
}

// The scale (input pixels per level pixel) of pyramid level `level`.
double levelScale(const mdbrief::PyramidOptions& pyramid, int level) {
  return std::pow(pyramid.scaleFactor, level - pyramid.firstLevel);
}

// The explicit ORB scheme and the library's defaults, for properties both must have.
std::vector<std::pair<std::string, DetectorOptions>> modOrbAndDefault() {
  return {{"modORB", modOrbOptions()}, {"default", DetectorOptions{}}};
}

// --- options and the per-level budget ---

TEST(FeaturesPerLevel, GeometricSharesThatAddUpToTheTotal) {
  const std::vector<int> shares = mdbrief::featuresPerLevel(1000, 8, 1.2);
  ASSERT_EQ(shares.size(), 8u);
  EXPECT_EQ(std::accumulate(shares.begin(), shares.end(), 0), 1000);
  // n0 = 1000 (1 - 1/1.2) / (1 - 1.2^-8) = 217.4
  EXPECT_EQ(shares[0], 217);
  for (size_t k = 1; k + 1 < shares.size(); ++k) {
    EXPECT_LT(shares[k], shares[k - 1]);
    EXPECT_NEAR(static_cast<double>(shares[k]) / shares[k - 1], 1 / 1.2, 0.01);
  }
  EXPECT_EQ(mdbrief::featuresPerLevel(500, 1, 1.2), std::vector<int>{500});
  EXPECT_THROW(mdbrief::featuresPerLevel(10, 0, 1.2), std::invalid_argument);
  EXPECT_THROW(mdbrief::featuresPerLevel(10, 3, 1.0), std::invalid_argument);
}

TEST(DetectorOptions, InvalidOptionsAreNamed) {
  const auto problem = [](const std::function<void(DetectorOptions&)>& change) {
    DetectorOptions options;
    change(options);
    return messageOf([&] { Detector detector(nullptr, options); });
  };
  EXPECT_NE(problem([](auto& o) { o.nfeatures = 0; }).find("nfeatures"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.pyramid.levels = 0; }).find("levels"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.pyramid.scaleFactor = 0.9; }).find("scaleFactor"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.threshold = 0; }).find("threshold"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.fallbackThreshold = 30; }).find("fallbackThreshold"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.harrisBlockSize = 6; }).find("harrisBlockSize"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.harrisK = -1; }).find("harrisK"), std::string::npos);
  EXPECT_NE(problem([](auto& o) { o.borderMargin = 10; }).find("borderMargin"), std::string::npos);
  EXPECT_NO_THROW(Detector(nullptr, DetectorOptions{}));
}

TEST(Detector, BadInputIsRejectedWithAReason) {
  const Detector detector;
  EXPECT_NE(messageOf([&] { detector.detect(cv::Mat()); }).find("empty"), std::string::npos);
  EXPECT_NE(messageOf([&] { detector.detect(cv::Mat(50, 50, CV_16UC1, cv::Scalar(0))); }).find("16UC1"),
            std::string::npos);
  const cv::Mat image(100, 120, CV_8UC1, cv::Scalar(0));
  EXPECT_NE(messageOf([&] { detector.detect(image, cv::Mat(100, 100, CV_8UC1, cv::Scalar(1))); }).find("mask"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { detector.detect(image, cv::Mat(100, 120, CV_32FC1, cv::Scalar(1))); }).find("mask"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { detector.detect(mdbrief::ImagePyramid()); }).find("empty"), std::string::npos);
  mdbrief::PyramidOptions other;
  other.scaleFactor = 1.5;
  EXPECT_NE(messageOf([&] { detector.detect(mdbrief::ImagePyramid(image, other)); }).find("scaleFactor"),
            std::string::npos);
  const Detector withCamera(std::make_shared<DiscCamera>(cv::Size(200, 100), cv::Point2d(100, 50), 50));
  EXPECT_NE(messageOf([&] { withCamera.detect(image); }).find("camera"), std::string::npos);
}

TEST(Detector, ImagesSmallerThanThePatchGiveNoKeypoints) {
  cv::Mat tiny(40, 40, CV_8UC1);
  cv::randu(tiny, 0, 256);
  for (const auto& [name, options] : modOrbAndDefault()) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(Detector(nullptr, options).detect(tiny).empty());
    EXPECT_TRUE(Detector(nullptr, options).detect(cv::Mat(1, 1, CV_8UC1, cv::Scalar(3))).empty());
  }
}

// --- output on a textured image ---

TEST(Detector, CountPropertiesAndOrderOnATexturedImage) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  for (const int nfeatures : {300, 1000}) {
    DetectorOptions options = modOrbOptions();
    options.nfeatures = nfeatures;
    const std::vector<cv::KeyPoint> keypoints = Detector(nullptr, options).detect(image);
    EXPECT_LE(static_cast<int>(keypoints.size()), nfeatures);
    EXPECT_GT(static_cast<double>(keypoints.size()), 0.8 * nfeatures);
    const mdbrief::ImagePyramid pyramid(image, options.pyramid);
    std::vector<int> perOctave(options.pyramid.levels, 0);
    for (size_t i = 0; i < keypoints.size(); ++i) {
      const cv::KeyPoint& kp = keypoints[i];
      ASSERT_GE(kp.octave, 0);
      ASSERT_LT(kp.octave, options.pyramid.levels);
      ++perOctave[kp.octave];
      const double scale = levelScale(options.pyramid, kp.octave);
      EXPECT_NEAR(kp.size, 31 * scale, 1e-3);
      EXPECT_GE(kp.angle, 0.f);
      EXPECT_LT(kp.angle, 360.f);
      // The whole rotated 32x32 patch (radius 16 sqrt 2 + 1 bilinear neighbour) at the level.
      const cv::Point2d level = pyramid.grid(kp.octave).toLevel(kp.pt);
      const cv::Size levelSize = pyramid.image(kp.octave).size();
      const double reach = 16 * std::sqrt(2.0) + 1;
      EXPECT_GE(level.x - reach, -1e-3);
      EXPECT_GE(level.y - reach, -1e-3);
      EXPECT_LE(level.x + reach, levelSize.width - 1 + 1e-3);
      EXPECT_LE(level.y + reach, levelSize.height - 1 + 1e-3);
      if (i > 0) {
        EXPECT_GE(keypoints[i - 1].response, kp.response);
      }
    }
    // Every level contributes, the finest the most.
    for (int level = 0; level < options.pyramid.levels; ++level) EXPECT_GT(perOctave[level], 0);
    EXPECT_EQ(std::max_element(perOctave.begin(), perOctave.end()) - perOctave.begin(), 0);
  }
}

TEST(Detector, SameInputGivesIdenticalKeypoints) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  // modORB with either corner detector, and the defaults; each keeping the strongest and spread.
  std::vector<std::pair<std::string, DetectorOptions>> configurations;
  for (const auto corners : {mdbrief::CornerDetector::Fast, mdbrief::CornerDetector::Agast}) {
    DetectorOptions o = modOrbOptions();
    o.corners = corners;
    configurations.emplace_back("modORB " + mdbrief::toString(corners), o);
  }
  configurations.emplace_back("default", DetectorOptions{});
  for (auto [name, options] : configurations) {
    for (const bool spread : {false, true}) {
      options.spread = spread;
      SCOPED_TRACE(name + (spread ? " spread" : " strongest"));
      const Detector detector(nullptr, options);
      const std::vector<cv::KeyPoint> first = detector.detect(image);
      const std::vector<cv::KeyPoint> second = detector.detect(image.clone());
      ASSERT_FALSE(first.empty());
      EXPECT_TRUE(identical(first, second));
      // A pyramid built by the caller (and shared with the descriptor) gives the same result.
      EXPECT_TRUE(identical(first, detector.detect(mdbrief::ImagePyramid(image, options.pyramid))));
      // Colour input is converted first.
      cv::Mat bgr;
      cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
      EXPECT_TRUE(identical(first, detector.detect(bgr)));
    }
  }
}

// Without angles (for a descriptor that measures its own) both methods return the same
// keypoints, only with angle -1.
TEST(Detector, KeypointsWithoutAnglesAreTheSameKeypoints) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  for (const auto method : {mdbrief::DetectorMethod::ModOrb, mdbrief::DetectorMethod::Hessian}) {
    DetectorOptions options;
    options.method = method;
    const Detector detector(nullptr, options);
    const mdbrief::ImagePyramid pyramid(image, options.pyramid);
    const std::vector<cv::KeyPoint> with = detector.detect(pyramid);
    std::vector<cv::KeyPoint> without = detector.detect(pyramid, {}, false);
    ASSERT_EQ(with.size(), without.size());
    ASSERT_FALSE(with.empty());
    EXPECT_TRUE(std::all_of(without.begin(), without.end(), [](const cv::KeyPoint& k) { return k.angle == -1.f; }));
    EXPECT_TRUE(std::any_of(with.begin(), with.end(), [](const cv::KeyPoint& k) { return k.angle > 0.f; }));
    for (size_t i = 0; i < with.size(); ++i) without[i].angle = with[i].angle;
    EXPECT_TRUE(identical(with, without));
  }
}

TEST(Detector, FallbackThresholdFindsCornersOnLowContrastImages) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  // Contrast divided by 5: most corners fall below threshold 20.
  cv::Mat faint;
  image.convertTo(faint, CV_8U, 0.2, 100);
  // The fallback is modORB's (FAST/AGAST thresholds).
  const DetectorOptions options = modOrbOptions();
  DetectorOptions strict = options;
  strict.fallbackThreshold = strict.threshold;
  const size_t withoutFallback = Detector(nullptr, strict).detect(faint).size();
  const size_t withFallback = Detector(nullptr, options).detect(faint).size();
  std::printf("low contrast: %zu keypoints without fallback, %zu with\n", withoutFallback, withFallback);
  EXPECT_GT(withFallback, withoutFallback + 200);
}

TEST(Detector, SpreadingCoversMoreOfTheImage) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  // Coverage: fraction of 40x40 cells of the image holding at least one level-0 keypoint.
  const auto coverage = [&](const std::vector<cv::KeyPoint>& keypoints) {
    const int cell = 40;
    cv::Mat hit = cv::Mat::zeros(image.rows / cell + 1, image.cols / cell + 1, CV_8UC1);
    for (const auto& kp : keypoints) hit.at<uchar>(int(kp.pt.y) / cell, int(kp.pt.x) / cell) = 1;
    return cv::countNonZero(hit) / static_cast<double>(hit.total());
  };
  // modORB's per-level quadtree (the Hessian's: HessianDetector.SpreadKeepsTheBudgetAndCoversMoreCells).
  DetectorOptions options = modOrbOptions();
  options.nfeatures = 500;
  const double plain = coverage(Detector(nullptr, options).detect(image));
  options.spread = true;
  const std::vector<cv::KeyPoint> spreadKeypoints = Detector(nullptr, options).detect(image);
  const double spread = coverage(spreadKeypoints);
  std::printf("coverage of 40x40 cells: %.3f strongest, %.3f spread\n", plain, spread);
  EXPECT_GT(spread, plain + 0.05);
  EXPECT_GT(spreadKeypoints.size(), 400u);
}

// --- masks ---

TEST(Detector, ExplicitMaskIsRespected) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::circle(mask, {300, 400}, 180, cv::Scalar(255), cv::FILLED);
  mask(cv::Rect(500, 50, 250, 200)).setTo(1);  // any nonzero value allows
  // The Hessian's keypoints sit at the sub-pixel refinement of a level's maximum, up to half a
  // level pixel from it: the mask is tested there, with or without an enlarged level.
  std::vector<std::pair<std::string, DetectorOptions>> configurations = modOrbAndDefault();
  DetectorOptions hessianOnOrbPyramid = modOrbOptions();
  hessianOnOrbPyramid.method = mdbrief::DetectorMethod::Hessian;
  configurations.emplace_back("Hessian on cv::ORB's pyramid", hessianOnOrbPyramid);
  for (const auto& [name, options] : configurations) {
    SCOPED_TRACE(name);
    const std::vector<cv::KeyPoint> keypoints = Detector(nullptr, options).detect(image, mask);
    EXPECT_GT(keypoints.size(), 300u);
    size_t inRectangle = 0;
    for (const auto& kp : keypoints) {
      EXPECT_NE(mask.at<uchar>(cvRound(kp.pt.y), cvRound(kp.pt.x)), 0) << kp.pt << " octave " << kp.octave;
      inRectangle += kp.pt.x >= 500 ? 1 : 0;
    }
    EXPECT_GT(inRectangle, 50u);
  }
}

TEST(Detector, ValidAreaMaskFollowsTheCamera) {
  const DiscCamera camera({200, 100}, {100, 50}, 40);
  const cv::Mat mask = mdbrief::validAreaMask(camera, camera.imageSize());
  ASSERT_EQ(mask.type(), CV_8UC1);
  ASSERT_EQ(mask.size(), cv::Size(200, 100));
  EXPECT_NEAR(cv::countNonZero(mask), CV_PI * 40 * 40, 0.02 * CV_PI * 40 * 40);
  EXPECT_EQ(mask.at<uchar>(50, 100), 255);
  EXPECT_EQ(mask.at<uchar>(50, 141), 0);
  EXPECT_EQ(mask.at<uchar>(5, 5), 0);
  // At another resolution the camera is resized, the disc with it.
  const cv::Mat half = mdbrief::validAreaMask(camera, {100, 50});
  EXPECT_NEAR(cv::countNonZero(half), CV_PI * 20 * 20, 0.04 * CV_PI * 20 * 20);
  EXPECT_THROW(mdbrief::validAreaMask(camera, {0, 10}), std::invalid_argument);
}

TEST(Detector, KeypointsKeepThePatchInsideTheCameraValidArea) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  const cv::Point2d centre(400, 320);
  const double radius = 300;
  for (const auto& [name, options] : modOrbAndDefault()) {
    SCOPED_TRACE(name);
    const Detector detector(std::make_shared<DiscCamera>(image.size(), centre, radius), options);
    const std::vector<cv::KeyPoint> keypoints = detector.detect(image);
    EXPECT_GT(keypoints.size(), 600u);
    double outermost = 0;
    for (const auto& kp : keypoints) {
      const double scale = levelScale(options.pyramid, kp.octave);
      const double r = std::hypot(kp.pt.x - centre.x, kp.pt.y - centre.y);
      // The patch (24 level pixels) stays inside the disc; one level pixel of slack for the
      // valid area's resampling.
      EXPECT_LE(r + 24 * scale, radius + scale) << kp.pt << " octave " << kp.octave;
      outermost = std::max(outermost, r + 24 * scale);
    }
    // ...and the detector does use the disc up to its rim, not some smaller area.
    EXPECT_GT(outermost, radius - 15);
  }
}

// --- Hessian (scale-space blobs) ---

// The Hessian on the default pyramid, named so that the tests stay about it whatever the default
// method is.
DetectorOptions hessianOptions(int nfeatures) {
  DetectorOptions o;
  o.method = mdbrief::DetectorMethod::Hessian;
  o.nfeatures = nfeatures;
  return o;
}

// Dark Gaussian blobs of known position and width on a grey background.
struct SyntheticBlob {
  cv::Point2d centre;
  double sigma;
  double depth = 150.0;  // grey levels below the background at the centre
};
cv::Mat blobImage(const std::vector<SyntheticBlob>& blobs) {
  cv::Mat image(480, 560, CV_32F, cv::Scalar(200));
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      for (const auto& b : blobs) {
        const double d2 = (x - b.centre.x) * (x - b.centre.x) + (y - b.centre.y) * (y - b.centre.y);
        image.at<float>(y, x) -= static_cast<float>(b.depth * std::exp(-d2 / (2 * b.sigma * b.sigma)));
      }
  cv::Mat out;
  image.convertTo(out, CV_8U);
  return out;
}

TEST(HessianDetector, FindsBlobsAtTheirSubPixelPositionWithSizesInProportion) {
  const std::vector<SyntheticBlob> blobs{{{120.3, 140.6}, 3.0}, {{330.5, 170.2}, 6.0}, {{250.7, 330.4}, 4.5}};
  const std::vector<cv::KeyPoint> kps = Detector(nullptr, hessianOptions(20)).detect(blobImage(blobs));
  std::vector<float> sizes;
  for (const auto& b : blobs) {
    const auto nearest = std::min_element(kps.begin(), kps.end(), [&](const cv::KeyPoint& a, const cv::KeyPoint& c) {
      return cv::norm(cv::Point2d(a.pt) - b.centre) < cv::norm(cv::Point2d(c.pt) - b.centre);
    });
    ASSERT_NE(nearest, kps.end());
    EXPECT_LT(cv::norm(cv::Point2d(nearest->pt) - b.centre), 0.35 * b.sigma) << b.centre << " " << nearest->pt;
    sizes.push_back(nearest->size);
  }
  // The scale follows the blob's width, between pyramid levels too (4.5 / 3 = 1.5 is not a power of
  // the scale factor).
  EXPECT_NEAR(sizes[1] / sizes[0], 2.0, 0.3);
  EXPECT_NEAR(sizes[2] / sizes[0], 1.5, 0.2);
}

// Wide blobs are found on coarse levels (scale 4 to 6): their keypoints must land on the blob
// centres in input pixels, which needs the levels' pixel centres (LevelGrid); level x times the
// scale misplaced them by half a level pixel and more (1.8 to 3.7 px here).
TEST(HessianDetector, WideBlobsFoundOnCoarseLevelsAreWhereTheyAre) {
  const std::vector<SyntheticBlob> blobs{{{140.3, 150.6}, 8.0}, {{380.5, 160.2}, 10.0}, {{260.7, 340.4}, 11.5}};
  const std::vector<cv::KeyPoint> kps = Detector(nullptr, hessianOptions(20)).detect(blobImage(blobs));
  for (const auto& b : blobs) {
    const auto nearest = std::min_element(kps.begin(), kps.end(), [&](const cv::KeyPoint& a, const cv::KeyPoint& c) {
      return cv::norm(cv::Point2d(a.pt) - b.centre) < cv::norm(cv::Point2d(c.pt) - b.centre);
    });
    ASSERT_NE(nearest, kps.end());
    std::printf("blob sigma %.1f: level %d, %.3f px off\n", b.sigma, nearest->octave, cv::norm(cv::Point2d(nearest->pt) - b.centre));
    EXPECT_GE(nearest->octave, 7) << b.centre;  // scale 1.25^6 = 3.8 and coarser
    EXPECT_LT(cv::norm(cv::Point2d(nearest->pt) - b.centre), 0.6) << b.centre << " " << nearest->pt;
  }
}

// Blobs of 3 to 12 px at random sub-pixel centres, found on levels 2 to 9: located again on the
// input (the default), their keypoints lie closer to the centres than the levels put them, whose
// bilinear reductions move each blob by a share of a level pixel that depends on where it falls.
TEST(HessianDetector, RelocalisedBlobsLieCloserToTheirCentresThanTheirLevelsPutThem) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> sub(0.0, 1.0), width(3.0, 12.0);
  std::vector<double> levelErrors, inputErrors;
  for (int image = 0; image < 8; ++image) {
    std::vector<SyntheticBlob> blobs;
    for (int row = 0; row < 3; ++row)
      for (int column = 0; column < 4; ++column)
        blobs.push_back({{70.0 + 140 * column + sub(rng), 80.0 + 150 * row + sub(rng)}, width(rng)});
    const cv::Mat picture = blobImage(blobs);
    DetectorOptions levels = hessianOptions(40);
    levels.relocalise = false;
    const std::vector<cv::KeyPoint> atLevels = Detector(nullptr, levels).detect(picture);
    const std::vector<cv::KeyPoint> onInput = Detector(nullptr, hessianOptions(40)).detect(picture);
    for (const auto& b : blobs) {
      const auto error = [&](const std::vector<cv::KeyPoint>& kps) {
        double best = INFINITY;
        for (const auto& k : kps) best = std::min(best, cv::norm(cv::Point2d(k.pt) - b.centre));
        return best;
      };
      // Blobs near the border lie within the margin of the level they would be found on.
      if (error(atLevels) > b.sigma / 2 || error(onInput) > b.sigma / 2) continue;
      levelErrors.push_back(error(atLevels));
      inputErrors.push_back(error(onInput));
    }
  }
  ASSERT_GE(levelErrors.size(), 30u);
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const auto worst = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
  std::printf("%zu blobs, distance to their centres, median / worst: levels %.3f / %.3f px, input %.3f / %.3f px\n", levelErrors.size(),
              median(levelErrors), worst(levelErrors), median(inputErrors), worst(inputErrors));
  // Measured: 0.043 / 0.126 px at the levels, 0.005 / 0.045 px located again.
  EXPECT_LT(median(inputErrors), 0.25 * median(levelErrors));
  EXPECT_LT(worst(inputErrors), 0.5 * worst(levelErrors));
}

// Three fine, deep blobs and three wide, shallower ones; a budget of three. The normalised
// determinant alone prefers the fine ones (it grows with the square of the depth and does not
// depend on the width); weighted by the scale, the wide ones win. The weight only ranks: every
// blob is found at the same position and size either way.
TEST(HessianDetector, TheScaleExponentLetsCoarseBlobsWinTheBudget) {
  const std::vector<SyntheticBlob> fine{{{100.3, 110.6}, 3.0}, {{260.5, 100.2}, 3.0}, {{420.7, 120.4}, 3.0}};
  const std::vector<SyntheticBlob> wide{
      {{150.2, 320.7}, 10.0, 100.0}, {{280.6, 330.3}, 10.0, 100.0}, {{410.4, 310.5}, 10.0, 100.0}};
  std::vector<SyntheticBlob> all = fine;
  all.insert(all.end(), wide.begin(), wide.end());
  const cv::Mat image = blobImage(all);
  const auto keptNear = [](const std::vector<cv::KeyPoint>& kps, const std::vector<SyntheticBlob>& blobs) {
    int n = 0;
    for (const auto& b : blobs)
      n += std::any_of(kps.begin(), kps.end(),
                       [&](const cv::KeyPoint& k) { return cv::norm(cv::Point2d(k.pt) - b.centre) < 0.35 * b.sigma; });
    return n;
  };
  DetectorOptions o = hessianOptions(3);
  o.hessianScaleExponent = 0.0;
  const auto byDeterminant = Detector(nullptr, o).detect(image);
  EXPECT_EQ(keptNear(byDeterminant, fine), 3);
  EXPECT_EQ(keptNear(byDeterminant, wide), 0);
  o.hessianScaleExponent = 1.0;
  const auto weighted = Detector(nullptr, o).detect(image);
  EXPECT_EQ(keptNear(weighted, wide), 3);
  EXPECT_EQ(keptNear(weighted, fine), 0);

  // Without a binding budget both keep every blob, at the same place and size.
  o.nfeatures = 1000;
  const auto every = Detector(nullptr, o).detect(image);
  o.hessianScaleExponent = 0.0;
  const auto everyUnweighted = Detector(nullptr, o).detect(image);
  ASSERT_EQ(every.size(), everyUnweighted.size());
  for (const auto& k : every) {
    const auto same = std::find_if(everyUnweighted.begin(), everyUnweighted.end(), [&](const cv::KeyPoint& u) {
      return u.pt == k.pt && u.size == k.size && u.octave == k.octave;
    });
    ASSERT_NE(same, everyUnweighted.end()) << k.pt;
    // The response is the weighted determinant: the one the budget ranked by.
    EXPECT_NEAR(k.response, same->response * k.size / 31.f, 1e-4f * k.response);
  }
}

// Elongated blobs turned by 45 degrees: the response's cross term moves the vertex off the row
// and column through the maximum pixel, which separate parabolas along x and y cannot see.
TEST(HessianDetector, TurnedElongatedBlobsAreLocatedByTheJointQuadratic) {
  cv::Mat image(480, 560, CV_32F, cv::Scalar(200));
  const std::vector<cv::Point2d> centres{{140.35, 150.65}, {300.6, 170.3}, {420.45, 330.55}, {200.7, 340.4}};
  const double along = 7.0, across = 2.5;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      for (size_t i = 0; i < centres.size(); ++i) {
        const double turn = (i % 2 ? -1 : 1) * CV_PI / 4;
        const double u = (x - centres[i].x) * std::cos(turn) + (y - centres[i].y) * std::sin(turn);
        const double v = -(x - centres[i].x) * std::sin(turn) + (y - centres[i].y) * std::cos(turn);
        image.at<float>(y, x) -= static_cast<float>(
            150.0 * std::exp(-u * u / (2 * along * along) - v * v / (2 * across * across)));
      }
  cv::Mat gray;
  image.convertTo(gray, CV_8U);
  const std::vector<cv::KeyPoint> kps = Detector(nullptr, hessianOptions(50)).detect(gray);
  double worst = 0;
  for (const cv::Point2d& c : centres) {
    double nearest = INFINITY;
    for (const cv::KeyPoint& k : kps) nearest = std::min(nearest, cv::norm(cv::Point2d(k.pt) - c));
    worst = std::max(worst, nearest);
  }
  // Separate parabolas: 0.59 px.
  EXPECT_LT(worst, 0.45) << "farthest blob centre from its keypoint, pixels";
}

// The same photo at 1 / 1.5 of its size: keypoints found in both agree in position and their
// sizes differ by the zoom.
TEST(HessianDetector, ScaleFollowsAZoom) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  const double zoom = 1.5;
  cv::Mat small;
  cv::resize(image, small, cv::Size(), 1 / zoom, 1 / zoom, cv::INTER_AREA);
  const Detector detector(nullptr, hessianOptions(500));
  const auto big = detector.detect(image), little = detector.detect(small);
  std::vector<double> ratios;
  for (const auto& k : little) {
    const cv::Point2d p(k.pt.x * zoom, k.pt.y * zoom);
    for (const auto& b : big)
      if (cv::norm(cv::Point2d(b.pt) - p) <= 2.0 * zoom) {
        ratios.push_back(b.size / k.size);
        break;
      }
  }
  ASSERT_GT(ratios.size(), little.size() / 3) << "few keypoints found again after the zoom";
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  EXPECT_NEAR(ratios[ratios.size() / 2], zoom, 0.15);
}

TEST(HessianDetector, BudgetOrderDeterminismAndTheCameraValidArea) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  const cv::Point2d centre(400, 320);
  const double radius = 300;
  // The default pyramid (with an enlarged level) and cv::ORB's.
  for (const mdbrief::PyramidOptions& pyramid : {DetectorOptions{}.pyramid, modOrbOptions().pyramid}) {
    SCOPED_TRACE("pyramid of " + std::to_string(pyramid.levels) + " levels of " + std::to_string(pyramid.scaleFactor) +
                 " from level " + std::to_string(pyramid.firstLevel));
    DetectorOptions options = hessianOptions(400);
    options.pyramid = pyramid;
    const Detector detector(std::make_shared<DiscCamera>(image.size(), centre, radius), options);
    const auto keypoints = detector.detect(image);
    EXPECT_EQ(keypoints.size(), 400u);
    EXPECT_TRUE(identical(keypoints, detector.detect(image)));
    for (size_t i = 0; i < keypoints.size(); ++i) {
      const auto& kp = keypoints[i];
      if (i > 0) {
        EXPECT_GE(keypoints[i - 1].response, kp.response);
      }
      // Maxima over both neighbouring levels: never on the first or last.
      EXPECT_GT(kp.octave, 0);
      EXPECT_LT(kp.octave, pyramid.levels - 1);
      const double scale = levelScale(pyramid, kp.octave);
      // Within half a level of its octave.
      EXPECT_LE(std::abs(std::log(kp.size / (31 * scale))), 0.5 * std::log(pyramid.scaleFactor) + 1e-6)
          << kp.size << " octave " << kp.octave;
      EXPECT_TRUE(kp.angle >= 0.f && kp.angle < 360.f);
      EXPECT_LE(std::hypot(kp.pt.x - centre.x, kp.pt.y - centre.y) + 24 * scale, radius + 2 * scale) << kp.pt;
    }
    // The descriptor, on the same pyramid, reads the size: it describes nearly all of them.
    std::vector<cv::KeyPoint> described = keypoints;
    cv::Mat descriptors;
    mdbrief::DescriptorOptions brief;
    brief.kind = mdbrief::DescriptorKind::Brief;
    mdbrief::DescriptorExtractor(nullptr, brief).compute(image, described, descriptors, cv::noArray(), pyramid);
    EXPECT_GT(described.size(), 0.95 * keypoints.size());
  }
}

TEST(HessianDetector, SpreadKeepsTheBudgetAndCoversMoreCells) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  DetectorOptions o = hessianOptions(300);
  const auto strongest = Detector(nullptr, o).detect(image);
  o.spread = true;
  const auto spread = Detector(nullptr, o).detect(image);
  EXPECT_LE(spread.size(), 300u);
  EXPECT_GT(spread.size(), 250u);
  const auto cells = [&](const std::vector<cv::KeyPoint>& kps) {
    std::set<std::pair<int, int>> used;
    for (const auto& k : kps) used.insert({static_cast<int>(k.pt.x) / 50, static_cast<int>(k.pt.y) / 50});
    return used.size();
  };
  EXPECT_GT(cells(spread), cells(strongest));
}

TEST(HessianDetector, InvalidOptionsAreNamed) {
  DetectorOptions o = hessianOptions(100);
  o.hessianSigma = 0.1;
  EXPECT_NE(messageOf([&] { Detector d(nullptr, o); }).find("hessianSigma"), std::string::npos);
  o = hessianOptions(100);
  o.hessianThreshold = -1;
  EXPECT_NE(messageOf([&] { Detector d(nullptr, o); }).find("hessianThreshold"), std::string::npos);
  o = hessianOptions(100);
  o.hessianScaleExponent = std::nan("");
  EXPECT_NE(messageOf([&] { Detector d(nullptr, o); }).find("hessianScaleExponent must be in [0, 4], got nan"),
            std::string::npos);
  o = hessianOptions(100);
  o.pyramid.levels = 2;
  EXPECT_NE(messageOf([&] { Detector d(nullptr, o); }).find("pyramid.levels must be in [3, 32], got 2"), std::string::npos);
}

// --- orientation ---

// The angle of a keypoint at the apex of a bright 90-degree wedge is the wedge's bisector
// (the intensity centroid lies on it), in image axes (y down).
TEST(Detector, OrientationPointsAlongTheBisectorOfAWedge) {
  for (const double bisector : {0.0, 37.0, 90.0, 135.0, 200.0, 290.0, 333.0}) {
    cv::Mat image(200, 200, CV_8UC1, cv::Scalar(40));
    const cv::Point apex(100, 100);
    cv::ellipse(image, apex, {60, 60}, 0, bisector - 45, bisector + 45, cv::Scalar(200), cv::FILLED,
                cv::LINE_AA);
    // A brighter apex: on a clean wedge FAST's scores tie around the apex and its
    // non-maximum suppression then removes them all. One pixel barely moves the centroid.
    image.at<uchar>(apex) = 255;
    // A FAST corner at the apex, on the input image alone.
    DetectorOptions options = modOrbOptions();
    options.pyramid.levels = 1;
    const std::vector<cv::KeyPoint> keypoints = Detector(nullptr, options).detect(image);
    const auto nearest = std::min_element(keypoints.begin(), keypoints.end(), [&](auto& a, auto& b) {
      return cv::norm(a.pt - cv::Point2f(apex)) < cv::norm(b.pt - cv::Point2f(apex));
    });
    ASSERT_NE(nearest, keypoints.end()) << "bisector " << bisector;
    ASSERT_LT(cv::norm(nearest->pt - cv::Point2f(apex)), 2.5) << "bisector " << bisector;
    const double error = std::remainder(nearest->angle - bisector, 360.0);
    EXPECT_LT(std::abs(error), 5.0) << "bisector " << bisector << " angle " << nearest->angle;
  }
}

TEST(Detector, AnglesTurnWithTheImage) {
  const cv::Mat image = textured();
  REQUIRE_IMAGE(image);
  cv::Mat rotated;
  cv::rotate(image, rotated, cv::ROTATE_90_CLOCKWISE);  // (x, y) -> (rows - 1 - y, x)
  for (const auto& [name, options] : modOrbAndDefault()) {
    SCOPED_TRACE(name);
    const Detector detector(nullptr, options);
    const std::vector<cv::KeyPoint> original = detector.detect(image);
    const std::vector<cv::KeyPoint> turned = detector.detect(rotated);
    int matched = 0, agreeing = 0;
    for (const auto& kp : original) {
      const cv::Point2f expected(image.rows - 1 - kp.pt.y, kp.pt.x);
      const double tolerance = 1.5 * levelScale(options.pyramid, kp.octave);
      // The nearest keypoint of the same octave: the first one within the tolerance may be a
      // neighbour.
      const cv::KeyPoint* found = nullptr;
      for (const auto& other : turned)
        if (other.octave == kp.octave && cv::norm(other.pt - expected) <= tolerance &&
            (!found || cv::norm(other.pt - expected) < cv::norm(found->pt - expected)))
          found = &other;
      if (!found) continue;
      ++matched;
      // Clockwise in the picture is +90 degrees in image axes (y down).
      if (std::abs(std::remainder(found->angle - kp.angle - 90.0, 360.0)) < 3.0) ++agreeing;
    }
    std::printf("%s, rotation by 90 degrees: %d of %zu keypoints found again, %d with angle +90 +- 3\n",
                name.c_str(), matched, original.size(), agreeing);
    EXPECT_GT(matched, 0.8 * original.size());
    EXPECT_GT(agreeing, 0.97 * matched);
  }
}

// --- repeatability under a known homography ---

// Fraction of keypoints of image 1 that, mapped by h into image 2 and landing inside it,
// have a keypoint of image 2 within 3 pixels.
double repeatability(const std::vector<cv::KeyPoint>& first, const std::vector<cv::KeyPoint>& second,
                     const cv::Matx33d& h, cv::Size secondSize) {
  int visible = 0, repeated = 0;
  for (const auto& kp : first) {
    const cv::Vec3d p = h * cv::Vec3d(kp.pt.x, kp.pt.y, 1.0);
    const cv::Point2d q(p[0] / p[2], p[1] / p[2]);
    if (q.x < 0 || q.y < 0 || q.x > secondSize.width - 1 || q.y > secondSize.height - 1) continue;
    ++visible;
    for (const auto& other : second) {
      if (std::hypot(other.pt.x - q.x, other.pt.y - q.y) <= 3.0) {
        ++repeated;
        break;
      }
    }
  }
  return visible == 0 ? 0.0 : static_cast<double>(repeated) / visible;
}

struct Pair {
  std::string name;
  cv::Mat first, second;
  cv::Matx33d h;
};

// defaultsFloor: the least repeatability the default detector (the Hessian's blobs) may have on
// the pair, a margin below the measured rate (its bits are the same on every CPU and SIMD level).
void expectAtLeastOrbRepeatability(const Pair& pair, double defaultsFloor) {
  ASSERT_FALSE(pair.first.empty()) << pair.name;
  ASSERT_FALSE(pair.second.empty()) << pair.name;
  const int nfeatures = 1000;
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(nfeatures);
  std::vector<cv::KeyPoint> orb1, orb2;
  orb->detect(pair.first, orb1);
  orb->detect(pair.second, orb2);
  const double orbRate = repeatability(orb1, orb2, pair.h, pair.second.size());
  const auto rateOf = [&](const DetectorOptions& options, const std::string& what) {
    const Detector detector(nullptr, options);
    const auto ours1 = detector.detect(pair.first), ours2 = detector.detect(pair.second);
    const double rate = repeatability(ours1, ours2, pair.h, pair.second.size());
    std::printf("%s repeatability within 3 px: %s %.3f (%zu/%zu keypoints), cv::ORB %.3f (%zu/%zu)\n",
                pair.name.c_str(), what.c_str(), rate, ours1.size(), ours2.size(), orbRate, orb1.size(), orb2.size());
    return rate;
  };
  // ORB's scheme on ORB's pyramid.
  DetectorOptions options = modOrbOptions();
  options.nfeatures = nfeatures;
  for (const bool spread : {false, true}) {
    for (const auto corners : {mdbrief::CornerDetector::Fast, mdbrief::CornerDetector::Agast}) {
      options.spread = spread;
      options.corners = corners;
      const double ourRate = rateOf(options, "modORB (" + mdbrief::toString(corners) + ", " +
                                                 (spread ? "spread" : "strongest") + ")");
      // modORB with its default corners and without spreading must do at least as well as cv::ORB.
      if (!spread && corners == DetectorOptions{}.corners) {
        EXPECT_GE(ourRate, orbRate - 0.02) << pair.name;
      }
    }
  }
  // The defaults' blobs, repeated within 3 px in the input image whatever their scale (below
  // ORB's corners on these pairs; docs/RESULTS.md has the tracker's repeatability).
  DetectorOptions defaults;
  defaults.nfeatures = nfeatures;
  EXPECT_GE(rateOf(defaults, "defaults (" + mdbrief::toString(defaults.method) + ")"), defaultsFloor) << pair.name;
}

TEST(DetectorRepeatability, OpencvDocGraf1To3AtLeastAsOrb) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir || !fs::exists(*dir / "graf3.png")) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc's graf images not found");
  cv::FileStorage fs((*dir / "H1to3p.xml").string(), cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat h;
  fs["H13"] >> h;
  ASSERT_EQ(h.size(), cv::Size(3, 3));
  // The defaults: 0.415 measured.
  expectAtLeastOrbRepeatability(
      {"opencv-doc graf 1->3", loadGrey(*dir / "graf1.png"), loadGrey(*dir / "graf3.png"), cv::Matx33d(h)}, 0.38);
}

TEST(DetectorRepeatability, OxfordGraf1To2AtLeastAsOrb) {
  MDBRIEF_REQUIRE_SHARED_DATA(data);
  const fs::path dir = data / "oxford-affine" / "graf";
  if (!fs::exists(dir / "img2.png") || !fs::exists(dir / "H1to2p")) MDBRIEF_SKIP_WITHOUT_DATA("Oxford graf not found");
  const cv::Matx33d h = mdbrief::readHomography(dir / "H1to2p");
  // The defaults: 0.608 measured.
  expectAtLeastOrbRepeatability({"Oxford graf 1->2", loadGrey(dir / "img1.png"), loadGrey(dir / "img2.png"), h}, 0.57);
}

}  // namespace

namespace mdbrief {
namespace {

// firstLevel > 0 adds enlarged levels: modORB's keypoints found there are smaller than the patch at the
// input scale, stay inside the input image, and the descriptor (on the same pyramid) can
// describe them.
// BRIEF on the detector's pyramid keeps all but a few keypoints: their levels are ones it reads.
void expectBriefDescribesAlmostAll(const ImagePyramid& pyramid, const std::vector<cv::KeyPoint>& keypoints) {
  DescriptorOptions descriptor;
  descriptor.kind = DescriptorKind::Brief;
  std::vector<cv::KeyPoint> described = keypoints;
  cv::Mat descriptors;
  DescriptorExtractor(nullptr, descriptor).compute(pyramid, described, descriptors);
  EXPECT_GT(described.size(), 0.95 * keypoints.size());
}

TEST(Detector, FirstLevelAddsEnlargedLevelsTheDescriptorUnderstands) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed (scripts/setup-deps.sh)");
  const cv::Mat image = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  DetectorOptions options = modOrbOptions();
  options.pyramid.firstLevel = 1;
  const ImagePyramid pyramid(image, options.pyramid);
  const std::vector<cv::KeyPoint> keypoints = Detector(nullptr, options).detect(pyramid);
  int enlarged = 0;
  for (const cv::KeyPoint& kp : keypoints) {
    ASSERT_TRUE(kp.pt.x >= 0 && kp.pt.y >= 0 && kp.pt.x < image.cols && kp.pt.y < image.rows);
    if (kp.octave == 0) {
      ++enlarged;
      EXPECT_NEAR(kp.size, 31.0 / 1.2, 1e-3);
    }
  }
  EXPECT_GT(enlarged, 50);
  expectBriefDescribesAlmostAll(pyramid, keypoints);
}

// The Hessian keeps maxima over both neighbouring levels, so never on the first level: with the
// input as the first level its finest blobs are a level coarser than the input. An enlarged
// level below the input (the defaults have one) lets the input level itself hold maxima: blobs
// finer than any the input's own pyramid gives, inside the image, and the descriptor (on the
// same pyramid) describes them.
TEST(HessianDetector, AnEnlargedLevelFindsBlobsAtTheInputScale) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed (scripts/setup-deps.sh)");
  const cv::Mat image = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  DetectorOptions options = hessianOptions(1000);
  options.pyramid.firstLevel = 1;
  // Without the enlarged level the finest maxima are on level 1, at most half a level finer.
  const double finestWithoutEnlarging = 31 * std::sqrt(options.pyramid.scaleFactor);
  const auto finer = [&](const std::vector<cv::KeyPoint>& keypoints) {
    return std::count_if(keypoints.begin(), keypoints.end(),
                         [&](const cv::KeyPoint& k) { return k.size < finestWithoutEnlarging - 1e-3; });
  };
  const ImagePyramid pyramid(image, options.pyramid);
  const std::vector<cv::KeyPoint> keypoints = Detector(nullptr, options).detect(pyramid);
  int atInput = 0;
  for (const cv::KeyPoint& kp : keypoints) {
    ASSERT_TRUE(kp.pt.x >= 0 && kp.pt.y >= 0 && kp.pt.x < image.cols && kp.pt.y < image.rows);
    if (kp.octave == options.pyramid.firstLevel) {
      ++atInput;
      EXPECT_LE(std::abs(std::log(kp.size / 31)), 0.5 * std::log(options.pyramid.scaleFactor) + 1e-6);
    }
  }
  EXPECT_GT(atInput, 50);
  EXPECT_GT(finer(keypoints), 50);
  expectBriefDescribesAlmostAll(pyramid, keypoints);

  options.pyramid.firstLevel = 0;
  EXPECT_EQ(finer(Detector(nullptr, options).detect(image)), 0);
}

}  // namespace
}  // namespace mdbrief
