// Every SIMD level (simd_level.hpp) gives the same descriptors, masks, angles and matches as
// the portable kernels. On this machine's CPU all levels it supports are compared; a build
// with MDBRIEF_PORTABLE_KERNELS has only the portable one (and the comparison is trivial).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "test_data.hpp"

namespace {

using mdbrief::SimdLevel;

// Restores the full level when a test ends, whatever it capped.
struct LevelCap {
  explicit LevelCap(SimdLevel level) { mdbrief::limitSimdLevel(level); }
  ~LevelCap() { mdbrief::limitSimdLevel(SimdLevel::Avx512); }
};

std::vector<SimdLevel> supportedLevels() {
  const std::vector<SimdLevel> levels = mdbrief::supportedSimdLevels();
  EXPECT_EQ(levels.front(), SimdLevel::Portable);  // the reference of every comparison
  return levels;
}

// Blurred noise: texture at every scale, so that every test of every keypoint matters.
cv::Mat texturedImage(int width, int height) {
  cv::Mat noise(height, width, CV_8U), img;
  cv::randu(noise, 0, 256);
  cv::GaussianBlur(noise, img, cv::Size(), 2.0);
  cv::normalize(img, img, 0, 255, cv::NORM_MINMAX);
  return img;
}

TEST(SimdLevel, CapLowersTheActiveLevel) {
  const SimdLevel supported = mdbrief::supportedSimdLevel();
  EXPECT_EQ(mdbrief::activeSimdLevel(), supported);
  EXPECT_EQ(mdbrief::supportedSimdLevels().back(), supported);
  {
    LevelCap cap(SimdLevel::Portable);
    EXPECT_EQ(mdbrief::activeSimdLevel(), SimdLevel::Portable);
    EXPECT_EQ(mdbrief::activeSimdTargetName(), "SCALAR");
  }
  EXPECT_EQ(mdbrief::activeSimdLevel(), supported);
  // Every level the CPU runs can be chosen; a cap picks the widest supported level within it.
  for (const SimdLevel level : mdbrief::supportedSimdLevels()) {
    LevelCap cap(level);
    EXPECT_EQ(mdbrief::activeSimdLevel(), level);
  }
  for (const auto& entry : mdbrief::kSimdLevelNames) {
    EXPECT_EQ(mdbrief::toString(entry.value), entry.name);
    EXPECT_EQ(mdbrief::parseSimdLevel(entry.name), entry.value);
  }
  try {
    mdbrief::parseSimdLevel("sse9");
    FAIL() << "an unknown level was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "SIMD level 'sse9' is not one of: portable, sse4, neon, avx2, avx512");
  }
#if defined(__x86_64__) && !defined(MDBRIEF_PORTABLE_KERNELS)
  // Every x86-64 CPU this project meets has SSE4.2; no x86 CPU has NEON.
  const std::vector<SimdLevel> levels = mdbrief::supportedSimdLevels();
  EXPECT_NE(std::find(levels.begin(), levels.end(), SimdLevel::Sse4), levels.end());
  EXPECT_EQ(std::find(levels.begin(), levels.end(), SimdLevel::Neon), levels.end());
  {
    LevelCap cap(SimdLevel::Neon);  // as wide as SSE4: the x86 level of that width
    EXPECT_EQ(mdbrief::activeSimdLevel(), SimdLevel::Sse4);
  }
#elif defined(MDBRIEF_PORTABLE_KERNELS)
  EXPECT_EQ(supported, SimdLevel::Portable);
#endif
}

// MDBRIEF_SIMD_LEVEL is read on the first kernel call of a process: a fresh process (the death
// test's "threadsafe" style runs this test again in a new one) with an unknown name is told the
// variable, its value and the names, one with a known name runs at that level, and an explicit
// level replaces a bad value (issue 45: limitSimdLevel threw it too, so nothing recovered).
TEST(SimdLevel, EnvironmentNamesTheLevel) {
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  const auto firstCall = [](bool limit) {
    try {
      if (limit) mdbrief::limitSimdLevel(SimdLevel::Portable);
      std::fprintf(stderr, "level %s\n", mdbrief::toString(mdbrief::activeSimdLevel()).c_str());
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "%s\n", e.what());
      std::exit(2);
    }
    std::exit(0);
  };
  for (const char* bad : {"avx1024", "AVX2", " avx2"}) {
    setenv("MDBRIEF_SIMD_LEVEL", bad, 1);
    EXPECT_EXIT(firstCall(false), ::testing::ExitedWithCode(2),
                "the environment variable MDBRIEF_SIMD_LEVEL is '" + std::string(bad) +
                    "', not a SIMD level: portable, sse4, neon, avx2, avx512")
        << bad;
    EXPECT_EXIT(firstCall(true), ::testing::ExitedWithCode(0), "level portable") << bad;
  }
  setenv("MDBRIEF_SIMD_LEVEL", "portable", 1);
  EXPECT_EXIT(firstCall(false), ::testing::ExitedWithCode(0), "level portable");
  unsetenv("MDBRIEF_SIMD_LEVEL");
}

// The pyramid's smoothing (the descriptors' bytes, and the floats at the same sigma 3 sigma wide)
// and the Hessian detector on it, for the narrowest, default and widest kernels.
TEST(SimdLevel, SmoothingAndBlobsAreIdenticalAtEveryLevel) {
  const cv::Mat image = texturedImage(403, 301);  // odd widths: every vector loop has a tail
  for (const auto& [taps, sigma] : {std::pair{1, 0.5}, {7, 2.0}, {31, 8.0}}) {
    mdbrief::PyramidOptions options;
    options.smoothingKernel = taps;
    options.smoothingSigma = sigma;
    std::vector<cv::Mat> refBytes, refFloats;
    for (const SimdLevel level : supportedLevels()) {
      LevelCap cap(level);
      const mdbrief::ImagePyramid pyramid(image, options);
      for (int k = 0; k < pyramid.levels(); ++k) {
        const cv::Mat& floats = pyramid.smoothedFloat(k, sigma);
        const cv::Mat& bytes = pyramid.smoothed(k);
        if (level == SimdLevel::Portable) {
          refFloats.push_back(floats), refBytes.push_back(bytes);
          continue;
        }
        const std::string what = mdbrief::toString(level) + ", " + std::to_string(taps) + " taps, level " + std::to_string(k);
        EXPECT_EQ(cv::norm(bytes, refBytes[k], cv::NORM_INF), 0.0) << what;
        EXPECT_EQ(cv::norm(floats, refFloats[k], cv::NORM_INF), 0.0) << what;
      }
    }
  }
  mdbrief::DetectorOptions hessian;
  hessian.method = mdbrief::DetectorMethod::Hessian;
  std::vector<cv::KeyPoint> reference;
  for (const SimdLevel level : supportedLevels()) {
    LevelCap cap(level);
    const std::vector<cv::KeyPoint> blobs = mdbrief::Detector(nullptr, hessian).detect(image);
    if (level == SimdLevel::Portable) {
      reference = blobs;
      ASSERT_GT(reference.size(), 100u);
      continue;
    }
    ASSERT_EQ(blobs.size(), reference.size()) << mdbrief::toString(level);
    for (size_t i = 0; i < blobs.size(); ++i) {
      EXPECT_EQ(blobs[i].pt, reference[i].pt) << mdbrief::toString(level);
      EXPECT_EQ(blobs[i].response, reference[i].response) << mdbrief::toString(level);
    }
  }
}

TEST(SimdLevel, DescriptorsAreIdenticalAtEveryLevel) {
  const auto camera = mdbrief::loadCamera((mdbrief::testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
  const cv::Mat image = texturedImage(camera->imageSize().width, camera->imageSize().height);
  const std::vector<cv::KeyPoint> detected = mdbrief::Detector(camera).detect(image);
  ASSERT_GT(detected.size(), 200u);
  for (const auto kind : {mdbrief::DescriptorKind::Brief, mdbrief::DescriptorKind::DBrief,
                          mdbrief::DescriptorKind::MdBrief, mdbrief::DescriptorKind::MaskedBrief}) {
    for (const int bits : {32, 256, 512}) {
      mdbrief::DescriptorOptions o;
      o.kind = kind;
      o.bits = bits;
      const mdbrief::DescriptorExtractor extractor(camera, o);
      std::vector<cv::KeyPoint> refKeypoints;
      cv::Mat refDesc, refMasks;
      for (const SimdLevel level : supportedLevels()) {
        LevelCap cap(level);
        std::vector<cv::KeyPoint> keypoints = detected;
        cv::Mat desc, masks;
        extractor.compute(image, keypoints, desc, masks);
        if (level == SimdLevel::Portable) {
          refKeypoints = keypoints, refDesc = desc, refMasks = masks;
          ASSERT_GT(desc.rows, 100);
          continue;
        }
        const std::string what = mdbrief::toString(level) + ", kind " + std::to_string(static_cast<int>(kind)) +
                                 ", " + std::to_string(bits) + " bits";
        ASSERT_EQ(keypoints.size(), refKeypoints.size()) << what;
        for (size_t i = 0; i < keypoints.size(); ++i) ASSERT_EQ(keypoints[i].angle, refKeypoints[i].angle) << what;
        EXPECT_EQ(cv::norm(desc, refDesc, cv::NORM_HAMMING), 0.0) << what;
        EXPECT_EQ(masks.size(), refMasks.size()) << what;
        if (!masks.empty()) {
          EXPECT_EQ(cv::norm(masks, refMasks, cv::NORM_HAMMING), 0.0) << what;
        }
      }
    }
  }
}

TEST(SimdLevel, MatchesAreIdenticalAtEveryLevel) {
  std::mt19937 rng(7);
  for (const int bytes : {4, 12, 32, 36, 64}) {
    // Few distinct byte values give many distance ties, which every kernel must break alike.
    cv::Mat query(150, bytes, CV_8U), train(333, bytes, CV_8U), qMasks(150, bytes, CV_8U), tMasks(333, bytes, CV_8U);
    for (cv::Mat* m : {&query, &train}) m->forEach<uint8_t>([&](uint8_t& v, const int*) { v = (rng() % 4) * 85; });
    for (cv::Mat* m : {&qMasks, &tMasks}) m->forEach<uint8_t>([&](uint8_t& v, const int*) { v = rng() % 3 ? 0xff : rng(); });
    tMasks.row(5).setTo(0);  // an all-zero mask counts as all ones
    mdbrief::MatchOptions options;
    options.crossCheck = true;
    options.ratio = 0.95f;
    std::vector<cv::DMatch> refPlain, refMasked;
    for (const SimdLevel level : supportedLevels()) {
      LevelCap cap(level);
      const auto plain = mdbrief::matchBruteForce(query, train, options);
      const auto masked = mdbrief::matchBruteForceMasked(query, qMasks, train, tMasks, options);
      if (level == SimdLevel::Portable) {
        refPlain = plain, refMasked = masked;
        ASSERT_FALSE(plain.empty());
        ASSERT_FALSE(masked.empty());
        continue;
      }
      for (const auto& [got, ref] : {std::pair{&plain, &refPlain}, std::pair{&masked, &refMasked}}) {
        ASSERT_EQ(got->size(), ref->size()) << mdbrief::toString(level) << ", " << bytes << " bytes";
        for (size_t i = 0; i < got->size(); ++i) {
          EXPECT_EQ((*got)[i].queryIdx, (*ref)[i].queryIdx);
          EXPECT_EQ((*got)[i].trainIdx, (*ref)[i].trainIdx);
          EXPECT_EQ((*got)[i].distance, (*ref)[i].distance);
        }
      }
    }
  }
}

}  // namespace
