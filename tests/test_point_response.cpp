// The Hessian response of a level at single pixels (detect/hessian.hpp PointResponse), which the
// detector reads instead of its finest level's whole response: the same bits at every pixel,
// border and beyond included, at every SIMD level, and the same blobs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "detect/hessian.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/base/simd_level.hpp"

namespace {

using mdbrief::SimdLevel;
using mdbrief::detail::HessianLevel;

struct LevelCap {
  explicit LevelCap(SimdLevel level) { mdbrief::limitSimdLevel(level); }
  ~LevelCap() { mdbrief::limitSimdLevel(SimdLevel::Avx512); }
};

// Noise over blobs, with runs of 0 and 255 (the extremes of every sum).
cv::Mat texture(cv::Size size, unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat noise(size, CV_8UC1), blobs;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) noise.at<uchar>(y, x) = static_cast<uchar>(rng() % 256);
  cv::GaussianBlur(noise, blobs, cv::Size(), 3.0);
  cv::Mat image = blobs + (noise - 128) / 4;
  for (int y = 0; y < size.height; y += 7) image.row(y).colRange(0, size.width / 3).setTo(y % 2 ? 255 : 0);
  return image;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(PointResponse, EqualsTheWholeLevelAtEveryPixel) {
  const cv::Size sizes[] = {{203, 157}, {61, 40}, {3, 3}, {2, 9}, {9, 1}};
  for (const SimdLevel level : mdbrief::supportedSimdLevels()) {
    LevelCap cap(level);
    for (const cv::Size size : sizes) {
      const cv::Mat image = texture(size, 7);
      for (const double sigma : {0.5, 2.0, 8.0}) {  // 1 tap each side, the default 6, the widest 24
        const std::string what = mdbrief::toString(level) + ", " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + ", sigma " + std::to_string(sigma);
        const cv::Mat response = mdbrief::detail::hessianLevel(image, sigma, false, 0.f, 1).response;
        const mdbrief::detail::PointResponse points(image, sigma);
        int compared = 0;
        for (int cy = -2; cy <= size.height + 1; ++cy)
          for (int cx = -2; cx <= size.width + 1; ++cx) {
            float expected = -INFINITY;
            if (cx >= 1 && cy >= 1 && cx < size.width - 1 && cy < size.height - 1) {
              for (int v = -1; v <= 1; ++v)
                for (int u = -1; u <= 1; ++u) expected = std::max(expected, response.at<float>(cy + v, cx + u));
              ++compared;
            }
            for (const float value : {expected, std::nextafter(expected, INFINITY)}) {
              float largest = 0.f;
              const bool exceeds = points.exceedsNeighbourhood(cx, cy, value, largest);
              ASSERT_TRUE(sameBits(largest, expected)) << what << " at " << cx << ", " << cy;
              ASSERT_EQ(exceeds, value > expected) << what << " at " << cx << ", " << cy;
            }
          }
        EXPECT_EQ(compared, std::max(size.width - 2, 0) * std::max(size.height - 2, 0)) << what;
      }
    }
  }
}

// The detector's maxima with the finest level read pixel by pixel: the same blobs, at the
// default margin and at the smallest (candidates next to the border).
TEST(PointResponse, FindsTheSameBlobsAsTheWholeLevel) {
  const cv::Mat image = texture({320, 240}, 11);
  mdbrief::PyramidOptions options{5, 1.25, 1, 13, 2.0};
  const mdbrief::ImagePyramid pyramid(image, options);
  std::vector<mdbrief::LevelGrid> grids;
  for (int k = 0; k < pyramid.levels(); ++k) grids.push_back(pyramid.grid(k));
  const auto all = [](int, int, int) { return true; };
  for (const int margin : {24, 1}) {
    std::vector<HessianLevel> levels;
    for (int k = 0; k < pyramid.levels(); ++k)
      levels.push_back(mdbrief::detail::hessianLevel(pyramid.image(k), 2.0, k > 0, 1e-6f, margin));
    const std::vector<mdbrief::detail::Blob> whole = mdbrief::detail::hessianMaxima(levels, grids, all);
    levels[0] = mdbrief::detail::hessianPoints(pyramid.image(0), 2.0);
    const std::vector<mdbrief::detail::Blob> points = mdbrief::detail::hessianMaxima(levels, grids, all);
    int onLevel1 = 0;
    ASSERT_EQ(points.size(), whole.size()) << "margin " << margin;
    for (size_t i = 0; i < whole.size(); ++i) {
      const mdbrief::detail::Blob &a = whole[i], &b = points[i];
      EXPECT_TRUE(a.level == b.level && a.x == b.x && a.y == b.y && sameBits(a.dx, b.dx) && sameBits(a.dy, b.dy) &&
                  sameBits(a.dlevel, b.dlevel) && sameBits(a.response, b.response))
          << "margin " << margin << ", blob " << i;
      onLevel1 += a.level == 1;
    }
    EXPECT_GT(onLevel1, 50) << "margin " << margin;  // the blobs that read level 0
  }
}

}  // namespace
