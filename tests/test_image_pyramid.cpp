#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "mdbrief/detect/image_pyramid.hpp"

namespace {

using mdbrief::ImagePyramid;
using mdbrief::PyramidOptions;
using mdbrief::toGrey;

cv::Mat noiseImage(cv::Size size) {
  cv::Mat image(size, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<no std::invalid_argument>";
}

TEST(ImagePyramid, LevelSizesAndScalesFollowTheScaleFactor) {
  const ImagePyramid pyramid(noiseImage({800, 640}), PyramidOptions{});
  ASSERT_EQ(pyramid.levels(), 8);
  // 800 / 1.2 = 666.7, 640 / 1.2 = 533.3; 800 / 1.44 = 555.6, 640 / 1.44 = 444.4;
  // 800 / 1.2^7 = 223.3, 640 / 1.2^7 = 178.6.
  EXPECT_EQ(pyramid.image(0).size(), cv::Size(800, 640));
  EXPECT_EQ(pyramid.image(1).size(), cv::Size(667, 533));
  EXPECT_EQ(pyramid.image(2).size(), cv::Size(556, 444));
  EXPECT_EQ(pyramid.image(7).size(), cv::Size(223, 179));
  for (int level = 0; level < pyramid.levels(); ++level) {
    EXPECT_NEAR(pyramid.scale(level), std::pow(1.2, level), 1e-12) << "level " << level;
    EXPECT_EQ(pyramid.image(level).type(), CV_8UC1);
  }
}

// On a ramp (intensity = input column, or row) bilinear resampling is exact up to rounding:
// a level pixel holds the input coordinate it was resampled at. Half the difference of a rising
// and a falling ramp cancels the 8-bit rounding's bias in intensity, and the mean over the
// level's middle its noise (the borders clamp). LevelGrid agrees within 0.02 to 0.09 px at every
// level of both axes; x * scale was off by up to 1.4 px (level 6).
TEST(ImagePyramid, LevelGridPlacesLevelPixelsWhereTheirValuesCameFrom) {
  const cv::Size size(250, 200);
  cv::Mat rising(size, CV_8UC1), falling(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      rising.at<uchar>(y, x) = static_cast<uchar>(x);
      falling.at<uchar>(y, x) = static_cast<uchar>(255 - x);
    }
  PyramidOptions options;
  options.firstLevel = 1;  // an enlarged level too
  for (const bool turned : {false, true}) {
    const auto axis = [&](const cv::Mat& m) { return turned ? cv::Mat(m.t()) : m; };
    const ImagePyramid up(axis(rising), options), down(axis(falling), options);
    ASSERT_EQ(up.levels(), options.levels);
    for (int level = 0; level < up.levels(); ++level) {
      const mdbrief::LevelGrid grid = up.grid(level);
      const cv::Mat a = axis(up.image(level)), b = axis(down.image(level));
      double error = 0;
      int n = 0;
      for (int x = a.cols / 8; x < a.cols * 7 / 8; ++x, ++n) {
        const double position = (a.at<uchar>(a.rows / 2, x) - b.at<uchar>(a.rows / 2, x) + 255) / 2.0;
        const cv::Point2d input = grid.toInput(turned ? cv::Point2d(0, x) : cv::Point2d(x, 0));
        error += position - (turned ? input.y : input.x);
        EXPECT_NEAR(grid.toLevel(input).x, turned ? 0 : x, 1e-9);
      }
      EXPECT_LT(std::abs(error / n), 0.15) << (turned ? "rows" : "columns") << ", level " << level;
    }
  }
}

TEST(ImagePyramid, OtherScaleFactorAndLevelCount) {
  PyramidOptions options;
  options.levels = 3;
  options.scaleFactor = 2.0;
  const ImagePyramid pyramid(noiseImage({100, 60}), options);
  ASSERT_EQ(pyramid.levels(), 3);
  EXPECT_EQ(pyramid.image(1).size(), cv::Size(50, 30));
  EXPECT_EQ(pyramid.image(2).size(), cv::Size(25, 15));
  EXPECT_DOUBLE_EQ(pyramid.scale(2), 4.0);
}

TEST(ImagePyramid, MaxLevelsLimitsTheLevelsBuilt) {
  const ImagePyramid pyramid(noiseImage({200, 100}), PyramidOptions{}, 3);
  EXPECT_EQ(pyramid.levels(), 3);
  EXPECT_THROW(pyramid.image(3), std::out_of_range);
}

TEST(ImagePyramid, StopsBeforeLevelsWouldBeEmpty) {
  // 1 / 1.2^4 = 0.48 rounds to 0: levels 0..3 only.
  const ImagePyramid pyramid(noiseImage({1, 1}), PyramidOptions{});
  EXPECT_EQ(pyramid.levels(), 4);
}

TEST(ImagePyramid, ResamplingPreservesConstantImagesAndMeanIntensity) {
  const ImagePyramid flat(cv::Mat(120, 160, CV_8UC1, cv::Scalar(77)), PyramidOptions{});
  for (int level = 0; level < flat.levels(); ++level) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(flat.image(level), &lo, &hi);
    EXPECT_EQ(lo, 77);
    EXPECT_EQ(hi, 77);
  }
  const cv::Mat noise = noiseImage({320, 240});
  const ImagePyramid pyramid(noise, PyramidOptions{});
  const double mean0 = cv::mean(noise)[0];
  for (int level = 1; level < pyramid.levels(); ++level)
    EXPECT_NEAR(cv::mean(pyramid.image(level))[0], mean0, 2.0) << "level " << level;
}

TEST(ImagePyramid, ColourInputIsConvertedToGrey) {
  cv::Mat colour(50, 60, CV_8UC3, cv::Scalar(10, 200, 30));
  const ImagePyramid pyramid(colour, PyramidOptions{});
  EXPECT_EQ(pyramid.image(0).type(), CV_8UC1);
  // 0.114 * 10 + 0.587 * 200 + 0.299 * 30 = 127.9
  EXPECT_EQ(pyramid.image(0).at<uchar>(10, 10), 128);
}

TEST(ImagePyramid, SmoothedLevelIsTheGaussianOfTheLevelAndIsCached) {
  PyramidOptions options;
  options.smoothingKernel = 11;  // 3 sigma wide, as the float levels are
  options.smoothingSigma = 1.5;
  const ImagePyramid pyramid(noiseImage({90, 70}), options);
  for (int level = 0; level < pyramid.levels(); ++level) {
    // The float level is the Gaussian of the intensities in [0, 1], and the 8-bit one rounds it,
    // both within the fixed-point weights' grey level (on noise, the harshest input).
    cv::Mat intensities, expected;
    pyramid.image(level).convertTo(intensities, CV_32F, 1.0 / 255.0);
    cv::GaussianBlur(intensities, expected, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT_101);
    const cv::Mat& smoothedFloat = pyramid.smoothedFloat(level, 1.5);
    ASSERT_EQ(smoothedFloat.type(), CV_32F);
    ASSERT_EQ(smoothedFloat.size(), expected.size());
    EXPECT_LT(cv::norm(smoothedFloat, expected, cv::NORM_INF), 1.0 / 255.0) << "level " << level;
    const cv::Mat& smoothed = pyramid.smoothed(level);
    cv::Mat rounded, bytesAsFloat;
    expected.convertTo(rounded, CV_8U, 255.0);
    EXPECT_LE(cv::norm(smoothed, rounded, cv::NORM_INF), 1) << "level " << level;
    // At the options' own Gaussian the two forms are one smoothing: the bytes are the floats rounded.
    smoothed.convertTo(bytesAsFloat, CV_32F, 1.0 / 255.0);
    EXPECT_LE(cv::norm(bytesAsFloat, smoothedFloat, cv::NORM_INF), (0.5 + 1e-3) / 255.0) << "level " << level;
    EXPECT_EQ(&pyramid.smoothed(level), &smoothed);
    EXPECT_EQ(pyramid.smoothed(level).data, smoothed.data);
    EXPECT_EQ(pyramid.smoothedFloat(level, 1.5).data, smoothedFloat.data);
    // Another sigma is another level (7 taps for sigma 1), and the first stays where it was.
    cv::Mat lighter;
    cv::GaussianBlur(intensities, lighter, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REFLECT_101);
    const cv::Mat& smoothedLighter = pyramid.smoothedFloat(level, 1.0);
    EXPECT_NE(smoothedLighter.data, smoothedFloat.data);
    EXPECT_LT(cv::norm(smoothedLighter, lighter, cv::NORM_INF), 1.0 / 255.0) << "level " << level;
    EXPECT_EQ(pyramid.smoothedFloat(level, 1.5).data, smoothedFloat.data);
  }
  // Smoothing actually happened: the noise's spread drops.
  cv::Scalar mean, rawStd, smoothStd;
  cv::meanStdDev(pyramid.image(0), mean, rawStd);
  cv::meanStdDev(pyramid.smoothed(0), mean, smoothStd);
  EXPECT_LT(smoothStd[0], 0.5 * rawStd[0]);
  EXPECT_THROW(pyramid.smoothed(pyramid.levels()), std::out_of_range);
  EXPECT_THROW(pyramid.smoothedFloat(pyramid.levels(), 1.0), std::out_of_range);
  for (const double bad : {0.0, -1.0, 8.01, std::nan("")}) EXPECT_THROW(pyramid.smoothedFloat(0, bad), std::invalid_argument) << bad;
}

// Several threads asking for the same float levels get one image each, the same for all.
TEST(ImagePyramid, FloatLevelsAreMadeOnceUnderConcurrentCalls) {
  const ImagePyramid pyramid(noiseImage({200, 150}), PyramidOptions{});
  std::vector<std::vector<const uchar*>> seen(8);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < seen.size(); ++t)
    threads.emplace_back([&, t] {
      for (int level = 0; level < pyramid.levels(); ++level) seen[t].push_back(pyramid.smoothedFloat(level, 1.0).data);
    });
  for (std::thread& t : threads) t.join();
  for (size_t t = 1; t < seen.size(); ++t) EXPECT_EQ(seen[t], seen[0]) << "thread " << t;
}

// The fixed-point weights sum to one exactly and are symmetric: a flat image stays flat and a
// ramp stays the same ramp away from the borders, exactly, for every kernel width the options
// accept, up to the widest (one tap: no smoothing at all).
TEST(ImagePyramid, SmoothingKeepsFlatImagesFlatAndRampsStraight) {
  for (const auto& [taps, sigma] : {std::pair{1, 0.3}, {3, 0.5}, {7, 2.0}, {15, 3.0}, {31, 8.0}}) {
    PyramidOptions options;
    options.levels = 1;
    options.smoothingKernel = taps;
    options.smoothingSigma = sigma;
    const std::string what = std::to_string(taps) + " taps, sigma " + std::to_string(sigma);
    const ImagePyramid flat(cv::Mat(40, 50, CV_8U, cv::Scalar(137)), options);
    EXPECT_EQ(cv::countNonZero(flat.smoothed(0) != 137), 0) << what;
    EXPECT_LT(cv::norm(flat.smoothedFloat(0, sigma), cv::Mat(40, 50, CV_32F, cv::Scalar(137.0 / 255.0)), cv::NORM_INF), 1e-6)
        << what;

    cv::Mat ramp(40, 100, CV_8U);
    for (int x = 0; x < ramp.cols; ++x) ramp.col(x).setTo(2 * x + 20);
    const ImagePyramid ramped(ramp, options);
    const cv::Rect inner(taps / 2, 0, ramp.cols - 2 * (taps / 2), ramp.rows);
    EXPECT_EQ(cv::countNonZero(ramped.smoothed(0)(inner) != ramp(inner)), 0) << what;
    // At the borders the reflection folds the ramp: smoothing lifts the lowest column there (sigma
    // 0.3 weighs its neighbours at 1/256, too little to tell).
    if (sigma >= 0.5) {
      EXPECT_GT(ramped.smoothedFloat(0, sigma).at<float>(0, 0), ramp.at<uchar>(0, 0) / 255.f + 1e-4f) << what;
    }
  }
}

// The borders reflect (BORDER_REFLECT_101): smoothing a level equals smoothing it padded with its
// reflection, whose rows and columns then need none, and keeping the middle. Levels from one pixel
// (reflected again and again) to wider than the kernel, odd and even heights (the column pass
// takes rows in pairs), and kernels whose centre weight (above one half) takes several terms.
TEST(ImagePyramid, SmoothedBordersAreTheReflectedLevelSmoothed) {
  for (const auto& [taps, sigma] : {std::pair{1, 0.3}, {3, 0.3}, {5, 0.6}, {13, 2.0}, {21, 3.0}, {31, 8.0}}) {
    PyramidOptions options;
    options.levels = 1;
    options.smoothingKernel = taps;
    options.smoothingSigma = sigma;
    // Padded as wide as the wider of the two smoothings: the bytes' kernel and the floats' 3 sigma.
    const int r = std::max(taps / 2, static_cast<int>(std::ceil(3.0 * sigma)));
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(3, 2), cv::Size(4, 5), cv::Size(13, 7), cv::Size(30, 14),
                                cv::Size(37, 29), cv::Size(80, 61)}) {
      const cv::Mat level = noiseImage(size);
      cv::Mat padded;
      cv::copyMakeBorder(level, padded, r, r, r, r, cv::BORDER_REFLECT_101);
      const ImagePyramid direct(level, options), reflected(padded, options);
      const cv::Rect middle(r, r, size.width, size.height);
      const std::string what = std::to_string(taps) + " taps, " + std::to_string(size.width) + "x" +
                               std::to_string(size.height);
      EXPECT_EQ(cv::norm(direct.smoothed(0), reflected.smoothed(0)(middle), cv::NORM_INF), 0.0) << what;
      EXPECT_EQ(cv::norm(direct.smoothedFloat(0, sigma), reflected.smoothedFloat(0, sigma)(middle), cv::NORM_INF), 0.0)
          << what;
    }
  }
}

// The descriptors' layout of the smoothed bytes: each pixel beside the one below it, the last
// row beside itself, at every level (odd widths leave the vector loops a tail), made once.
TEST(ImagePyramid, SmoothedPairsHoldEachPixelAndTheOneBelowIt) {
  const ImagePyramid pyramid(noiseImage({93, 71}), PyramidOptions{});
  for (int level = 0; level < pyramid.levels(); ++level) {
    const cv::Mat& bytes = pyramid.smoothed(level);
    const cv::Mat& pairs = pyramid.smoothedPairs(level);
    ASSERT_EQ(pairs.type(), CV_8UC2);
    ASSERT_EQ(pairs.size(), bytes.size());
    int wrong = 0;
    for (int y = 0; y < bytes.rows; ++y)
      for (int x = 0; x < bytes.cols; ++x) {
        const cv::Vec2b p = pairs.at<cv::Vec2b>(y, x);
        wrong += p[0] != bytes.at<uchar>(y, x) || p[1] != bytes.at<uchar>(std::min(y + 1, bytes.rows - 1), x);
      }
    EXPECT_EQ(wrong, 0) << "level " << level;
    EXPECT_EQ(pyramid.smoothedPairs(level).data, pairs.data);
  }
  EXPECT_THROW(pyramid.smoothedPairs(pyramid.levels()), std::out_of_range);
}

// Counts the cv::Mat buffers made while it is OpenCV's default allocator (for as long as it
// lives): the smoothed levels are made on first use, so only the buffers made tell a level that
// prepareSmoothed() made from one that smoothed() makes when asked.
class CountingAllocator : public cv::MatAllocator {
 public:
  CountingAllocator() : previous_(cv::Mat::getDefaultAllocator()) { cv::Mat::setDefaultAllocator(this); }
  ~CountingAllocator() override { cv::Mat::setDefaultAllocator(previous_); }
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, cv::AccessFlag flags,
                         cv::UMatUsageFlags usage) const override {
    ++made;
    return cv::Mat::getStdAllocator()->allocate(dims, sizes, type, data, step, flags, usage);
  }
  bool allocate(cv::UMatData* data, cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    return cv::Mat::getStdAllocator()->allocate(data, flags, usage);
  }
  void deallocate(cv::UMatData* data) const override { cv::Mat::getStdAllocator()->deallocate(data); }
  mutable std::atomic<int> made{0};

 private:
  cv::MatAllocator* previous_;
};

TEST(ImagePyramid, PrepareSmoothedFillsTheLevelsUpToMaxLevel) {
  const ImagePyramid pyramid(noiseImage({200, 160}), PyramidOptions{});
  ASSERT_GE(pyramid.levels(), 5);
  const CountingAllocator buffers;
  pyramid.prepareSmoothed(2);
  const int prepared = buffers.made;
  EXPECT_GE(prepared, 3) << "a buffer at least for each of levels 0..2";
  std::vector<const uchar*> data;
  for (int level = 0; level <= 2; ++level) data.push_back(pyramid.smoothed(level).data);
  EXPECT_EQ(buffers.made, prepared) << "levels 0..2 were ready";
  pyramid.smoothed(3);
  const int firstUse = buffers.made;
  EXPECT_GT(firstUse, prepared) << "level 3 is made on first use";
  pyramid.prepareSmoothed(-1);
  const int all = buffers.made;
  EXPECT_GT(all, firstUse) << "levels 4.. made by prepareSmoothed(-1)";
  for (int level = 0; level < pyramid.levels(); ++level) EXPECT_FALSE(pyramid.smoothed(level).empty());
  EXPECT_EQ(buffers.made, all) << "every level was ready";
  for (int level = 0; level <= 2; ++level) EXPECT_EQ(pyramid.smoothed(level).data, data[level]) << "not made again";
}

// Threads that ask for the same level at once all get the finished blur: none sees a level
// that another thread is still writing, and the level is blurred once (one buffer).
TEST(ImagePyramid, SmoothedIsSafeFromSeveralThreads) {
  const ImagePyramid pyramid(noiseImage({1600, 1200}), PyramidOptions{});
  // What one thread gets from its own pyramid of the same image.
  const ImagePyramid alone(noiseImage({1600, 1200}), PyramidOptions{});
  std::vector<cv::Mat> expected(pyramid.levels());
  for (int level = 0; level < pyramid.levels(); ++level) expected[level] = alone.smoothed(level);
  constexpr int kThreads = 8;
  std::atomic<int> ready{0};
  std::vector<std::vector<const uchar*>> seen(kThreads, std::vector<const uchar*>(pyramid.levels()));
  std::vector<int> wrong(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      ++ready;
      while (ready < kThreads) std::this_thread::yield();
      for (int level = 0; level < pyramid.levels(); ++level) {
        const cv::Mat& smoothed = pyramid.smoothed(level);
        seen[t][level] = smoothed.data;
        if (smoothed.size() != expected[level].size() || cv::norm(smoothed, expected[level], cv::NORM_INF) != 0)
          ++wrong[t];
      }
    });
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(wrong[t], 0) << "thread " << t;
    EXPECT_EQ(seen[t], seen[0]) << "thread " << t;
  }
}

TEST(ImagePyramid, RejectsBadInputAndOptions) {
  EXPECT_NE(messageOf([] { ImagePyramid(cv::Mat(), PyramidOptions{}); }).find("empty"), std::string::npos);
  EXPECT_NE(messageOf([] { ImagePyramid(cv::Mat(10, 10, CV_32FC1, cv::Scalar(0)), PyramidOptions{}); })
                .find("32FC1"),
            std::string::npos);
  PyramidOptions options;
  options.levels = 0;
  EXPECT_NE(messageOf([&] { ImagePyramid(noiseImage({10, 10}), options); }).find("levels"), std::string::npos);
  options = {};
  options.scaleFactor = 1.0;
  EXPECT_NE(messageOf([&] { ImagePyramid(noiseImage({10, 10}), options); }).find("scaleFactor"),
            std::string::npos);
  options = {};
  options.smoothingKernel = 4;
  EXPECT_NE(messageOf([&] { ImagePyramid(noiseImage({10, 10}), options); }).find("smoothingKernel"),
            std::string::npos);
  options = {};
  options.smoothingSigma = 0.0;
  EXPECT_NE(messageOf([&] { ImagePyramid(noiseImage({10, 10}), options); }).find("smoothingSigma"),
            std::string::npos);
}

TEST(ImagePyramid, FirstLevelHoldsTheInputAndLowerLevelsEnlargeIt) {
  cv::Mat image(240, 320, CV_8UC1);
  cv::randu(image, 0, 256);
  PyramidOptions options;
  options.levels = 5;
  options.firstLevel = 2;
  const ImagePyramid pyramid(image, options);
  ASSERT_EQ(pyramid.levels(), 5);
  EXPECT_EQ(pyramid.inputSize(), image.size());
  EXPECT_EQ(pyramid.image(2).data, image.data);  // the input itself, not a copy
  EXPECT_DOUBLE_EQ(pyramid.scale(2), 1.0);
  EXPECT_NEAR(pyramid.scale(0), 1.0 / 1.44, 1e-12);
  EXPECT_NEAR(pyramid.scale(4), 1.44, 1e-12);
  EXPECT_EQ(pyramid.image(0).size(), cv::Size(461, 346));  // 320 * 1.44, 240 * 1.44 rounded
  EXPECT_EQ(pyramid.image(4).size(), cv::Size(222, 167));
  options.firstLevel = 5;
  EXPECT_THROW(ImagePyramid(image, options), std::invalid_argument);
}

// Issue 29: --levels 32 --scale-factor 2 --first-level 10, all within the ranges, asked for
// 378 GB. Level 0 enlarges the input at most 4 times per side.
TEST(ImagePyramid, TheEnlargementOfTheFirstLevelIsBounded) {
  PyramidOptions options;
  options.levels = 32;
  options.scaleFactor = 2.0;
  options.firstLevel = 10;
  try {
    validate(options);
    ADD_FAILURE() << "first level 10 of factor 2 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("[0, 2]"), std::string::npos) << e.what();
  }
  options.firstLevel = 2;  // 4 times per side
  EXPECT_NO_THROW(validate(options));
  options.scaleFactor = 1.2;
  options.firstLevel = 7;  // 1.2^7 = 3.6
  EXPECT_NO_THROW(validate(options));
  options.firstLevel = 8;  // 4.3
  EXPECT_THROW(validate(options), std::invalid_argument);
}

TEST(ToGrey, GreyInputIsReturnedWithoutCopy) {
  const cv::Mat grey = noiseImage({20, 10});
  const cv::Mat out = toGrey(grey);
  EXPECT_EQ(out.data, grey.data);
  EXPECT_EQ(out.type(), CV_8UC1);
}

TEST(ToGrey, ColourUsesBgrOrderAndIgnoresAlpha) {
  // Pure blue, green and red in BGR order: luma weights 0.114, 0.587, 0.299.
  cv::Mat bgr(1, 3, CV_8UC3);
  bgr.at<cv::Vec3b>(0, 0) = {255, 0, 0};
  bgr.at<cv::Vec3b>(0, 1) = {0, 255, 0};
  bgr.at<cv::Vec3b>(0, 2) = {0, 0, 255};
  const cv::Mat grey3 = toGrey(bgr);
  ASSERT_EQ(grey3.type(), CV_8UC1);
  EXPECT_NEAR(grey3.at<uchar>(0, 0), 29, 1);
  EXPECT_NEAR(grey3.at<uchar>(0, 1), 150, 1);
  EXPECT_NEAR(grey3.at<uchar>(0, 2), 76, 1);

  cv::Mat bgra(1, 3, CV_8UC4);
  bgra.at<cv::Vec4b>(0, 0) = {255, 0, 0, 0};
  bgra.at<cv::Vec4b>(0, 1) = {0, 255, 0, 17};
  bgra.at<cv::Vec4b>(0, 2) = {0, 0, 255, 255};
  const cv::Mat grey4 = toGrey(bgra);
  ASSERT_EQ(grey4.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(grey4, grey3, cv::NORM_INF), 0);
}

TEST(ToGrey, RejectsEmptyAndUnsupportedTypes) {
  EXPECT_NE(messageOf([] { toGrey(cv::Mat()); }).find("empty"), std::string::npos);
  for (const int type : {CV_8UC2, CV_16UC1, CV_16SC3, CV_32FC1, CV_64FC1}) {
    const cv::Mat image(4, 4, type, cv::Scalar::all(0));
    const std::string message = messageOf([&] { toGrey(image); });
    EXPECT_NE(message.find(cv::typeToString(type)), std::string::npos) << message;
  }
}

}  // namespace
