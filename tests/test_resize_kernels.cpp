// The pyramid's bilinear resizing (detect/resize_kernels.hpp): the same bits at every SIMD level
// the CPU runs, and, against the OpenCV it was measured on, cv::resize(INTER_LINEAR)'s bits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core/version.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/resize_kernels.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/base/simd_level.hpp"

namespace {

using mdbrief::SimdLevel;
namespace rk = mdbrief::resize_kernels;

// The kernel reproduces OpenCV 4.6's fixed point (its weights, the vertical pass's rounding),
// which another release may change: the comparison with cv::resize holds for 4.6 only.
constexpr bool kOpenCv46 = CV_VERSION_MAJOR == 4 && CV_VERSION_MINOR == 6;

struct LevelCap {
  explicit LevelCap(SimdLevel level) { mdbrief::limitSimdLevel(level); }
  ~LevelCap() { mdbrief::limitSimdLevel(SimdLevel::Avx512); }
};

cv::Mat kernelResize(const cv::Mat& src, cv::Size size) {
  cv::Mat dst(size, CV_8UC1);
  rk::resizeLinear(src.data, src.step, src.cols, src.rows, dst.data, dst.step, size.width, size.height);
  return dst;
}

// Noise, noise with runs of 0 and 255 (the extremes of every sum), or all white.
cv::Mat content(cv::Size size, int kind, std::mt19937& rng) {
  cv::Mat image(size, CV_8UC1);
  if (kind == 2) return image.setTo(255);
  cv::randu(image, 0, 256);
  if (kind == 1)
    for (int y = 0; y < size.height; ++y)
      for (int x = 0; x < size.width; ++x)
        if (rng() % 3 != 0) image.at<uchar>(y, x) = ((x / 5 + y / 3) & 1) ? 255 : 0;
  return image;
}

struct Case {
  cv::Size src, dst;
};

// Each level of ImagePyramid's chain: the size from the input's, the pixels from the level before.
std::vector<Case> pyramidChain(cv::Size input, double factor, int levels) {
  std::vector<Case> cases;
  cv::Size previous = input;
  for (int level = 1; level < levels; ++level) {
    const double scale = std::pow(factor, level);
    const cv::Size size(static_cast<int>(std::lround(input.width / scale)),
                        static_cast<int>(std::lround(input.height / scale)));
    if (size.width < 1 || size.height < 1) break;
    cases.push_back({previous, size});
    previous = size;
  }
  return cases;
}

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (const cv::Size input : {cv::Size(754, 480), cv::Size(752, 480), cv::Size(640, 480)})
    for (const double factor : {1.2, 1.5, 1.1, 2.0})
      for (const Case& c : pyramidChain(input, factor, 12)) cases.push_back(c);
  std::mt19937 rng(11);
  for (int i = 0; i < 300; ++i) {
    const cv::Size src(1 + static_cast<int>(rng() % 1200), 1 + static_cast<int>(rng() % (i % 10 == 0 ? 1200 : 200)));
    // Half of them at the pyramid's ratios (up to 2), the rest anywhere down to one pixel.
    const double ratio = i % 2 ? 1 + (rng() % 1001) / 1000.0 : 0;
    const auto reduce = [&](int n) {
      return ratio > 0 ? std::max(1, static_cast<int>(std::lround(n / ratio))) : 1 + static_cast<int>(rng() % n);
    };
    const int width = reduce(src.width), height = reduce(src.height);
    cases.push_back({src, {width, height}});
  }
  // Enlargements: the pyramid's levels below the input (up to 4 times per side), and anywhere up
  // to 8 times, from one pixel on.
  for (const cv::Size input : {cv::Size(754, 480), cv::Size(752, 480), cv::Size(640, 480), cv::Size(37, 23)})
    for (const double factor : {1.25, 1.2, 1.5, 2.0})
      for (int below = 1; below <= 6 && std::pow(factor, below) <= 4.0; ++below) {
        const double scale = std::pow(factor, below);
        cases.push_back({input, {static_cast<int>(std::lround(input.width * scale)),
                                 static_cast<int>(std::lround(input.height * scale))}});
      }
  for (int i = 0; i < 150; ++i) {
    const cv::Size src(1 + static_cast<int>(rng() % 300), 1 + static_cast<int>(rng() % 100));
    const auto enlarge = [&](int n) { return n + static_cast<int>(rng() % (7 * n + 1)); };
    cases.push_back({src, {enlarge(src.width), enlarge(src.height)}});
  }
  // One axis enlarged, the other reduced.
  cases.push_back({{100, 60}, {131, 45}});
  cases.push_back({{100, 60}, {37, 75}});
  // Exactly half (OpenCV's INTER_AREA, the same rounded mean of four), the same size, one axis
  // kept, and one pixel.
  for (const Case& c : std::vector<Case>{{{754, 480}, {377, 240}}, {{34, 18}, {17, 9}}, {{100, 60}, {100, 60}},
                                         {{100, 60}, {100, 45}}, {{100, 60}, {37, 60}}, {{1, 1}, {1, 1}},
                                         {{300, 7}, {1, 1}}, {{7, 300}, {7, 1}}})
    cases.push_back(c);
  return cases;
}

TEST(ResizeKernels, EveryLevelGivesThePortableBitsAndOpenCvs) {
  if (!kOpenCv46) std::printf("OpenCV %s: the comparison with cv::resize is skipped\n", CV_VERSION);
  const std::vector<SimdLevel> levels = mdbrief::supportedSimdLevels();
  ASSERT_EQ(levels.front(), SimdLevel::Portable);
  std::mt19937 rng(5);
  int compared = 0;
  for (const Case& c : allCases()) {
    const cv::Mat src = content(c.src, compared % 3, rng);
    const std::string what = std::to_string(c.src.width) + "x" + std::to_string(c.src.height) + " -> " +
                             std::to_string(c.dst.width) + "x" + std::to_string(c.dst.height);
    cv::Mat portable;
    {
      const LevelCap cap(SimdLevel::Portable);
      portable = kernelResize(src, c.dst);
    }
    if (kOpenCv46) {
      cv::Mat expected;
      cv::resize(src, expected, c.dst, 0, 0, cv::INTER_LINEAR);
      ASSERT_EQ(cv::norm(portable, expected, cv::NORM_INF), 0) << what;
    }
    for (const SimdLevel level : levels) {
      const LevelCap cap(level);
      ASSERT_EQ(cv::norm(kernelResize(src, c.dst), portable, cv::NORM_INF), 0)
          << what << " at " << mdbrief::toString(level);
    }
    ++compared;
  }
  EXPECT_GT(compared, 500);
}

// The halving that blob localisation reads (cv::pyrDown's integer arithmetic, which no OpenCV
// release has changed): every size from one pixel on, borders of both parities, a source that is
// part of a wider image, at every level.
TEST(ResizeKernels, HalvingIsPyrDownAtEveryLevel) {
  std::vector<cv::Size> sizes;
  for (int w = 1; w <= 72; ++w) sizes.push_back({w, 1 + (w * 7) % 23});
  for (int h = 1; h <= 12; ++h) sizes.push_back({h % 2 ? 129 : 130, h});
  for (const cv::Size s : {cv::Size(754, 480), cv::Size(752, 480), cv::Size(800, 640), cv::Size(1, 300)})
    sizes.push_back(s);
  std::mt19937 rng(17);
  for (int i = 0; i < 40; ++i)
    sizes.push_back({1 + static_cast<int>(rng() % 1300), 1 + static_cast<int>(rng() % 90)});
  int compared = 0;
  for (const cv::Size size : sizes) {
    // Inside a wider image: the kernel follows the stride and reads no pixel beyond the source.
    cv::Mat wide(size.height, size.width + 9, CV_8UC1);
    cv::randu(wide, 0, 256);
    cv::Mat src = wide.colRange(3, 3 + size.width);
    content(size, compared % 3, rng).copyTo(src);
    wide.colRange(0, 3).setTo(255), wide.colRange(3 + size.width, wide.cols).setTo(255);
    cv::Mat expected;
    cv::pyrDown(src, expected);
    const std::string what = std::to_string(size.width) + "x" + std::to_string(size.height);
    for (const SimdLevel level : mdbrief::supportedSimdLevels()) {
      const LevelCap cap(level);
      cv::Mat half(expected.size(), CV_8UC1, cv::Scalar(7));
      rk::halveImage(src.data, src.step, src.cols, src.rows, half.data, half.step);
      ASSERT_EQ(cv::norm(half, expected, cv::NORM_INF), 0) << what << " at " << mdbrief::toString(level);
    }
    ++compared;
  }
  EXPECT_GT(compared, 120);
}

// The pyramid's levels, reduced and enlarged by the kernel, are cv::resize's chain.
TEST(ResizeKernels, PyramidLevelsAreOpenCvsChain) {
  if (!kOpenCv46) GTEST_SKIP() << "the kernel reproduces OpenCV 4.6, this is " CV_VERSION;
  std::mt19937 rng(3);
  const cv::Mat input = content({754, 480}, 0, rng);
  mdbrief::PyramidOptions options;
  options.firstLevel = 1;
  const mdbrief::ImagePyramid pyramid(input, options);
  cv::Mat expected;
  cv::resize(input, expected, pyramid.image(0).size(), 0, 0, cv::INTER_LINEAR);
  EXPECT_EQ(cv::norm(pyramid.image(0), expected, cv::NORM_INF), 0);
  cv::Mat previous = input;
  for (int level = 2; level < pyramid.levels(); ++level) {
    cv::resize(previous, expected, pyramid.image(level).size(), 0, 0, cv::INTER_LINEAR);
    EXPECT_EQ(cv::norm(pyramid.image(level), expected, cv::NORM_INF), 0) << "level " << level;
    previous = expected;
  }
}

}  // namespace
