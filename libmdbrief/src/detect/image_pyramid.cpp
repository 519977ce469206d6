#include "mdbrief/detect/image_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <list>
#include <mutex>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "detect/gaussian_smoothing.hpp"
#include "detect/resize_kernels.hpp"
#include "detect/smoothing_kernels.hpp"
#include "mdbrief/base/simd_level.hpp"

namespace mdbrief {

struct ImagePyramid::SmoothedLevels {
  explicit SmoothedLevels(size_t levels)
      : bytes(levels), pairs(levels), byteOnce(levels), pairOnce(levels), floatMutex(levels), floats(levels) {}
  std::vector<cv::Mat> bytes, pairs;
  std::vector<std::once_flag> byteOnce, pairOnce;
  // The float levels by sigma, a list per level so that a returned level never moves: a caller
  // asks for one or two sigmas. A lock per level: threads wanting other levels do not wait.
  struct FloatLevel {
    double sigma;
    cv::Mat image;
  };
  std::vector<std::mutex> floatMutex;
  std::vector<std::list<FloatLevel>> floats;
};

cv::Mat toGrey(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("toGrey: the image is empty");
  switch (image.type()) {
    case CV_8UC1:
      return image;
    case CV_8UC3: {
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
      return grey;
    }
    case CV_8UC4: {
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
      return grey;
    }
    default:
      throw std::invalid_argument("toGrey: unsupported image type " +
                                  cv::typeToString(image.type()) +
                                  " (expected 8UC1, 8UC3 or 8UC4)");
  }
}

ImagePyramid::ImagePyramid(const cv::Mat& image, const PyramidOptions& options, int maxLevels)
    : options_(options) {
  validate(options);
  const cv::Mat grey = toGrey(image);
  inputSize_ = grey.size();
  const int wanted = maxLevels < 0 ? options.levels : std::min(options.levels, maxLevels);
  images_.reserve(wanted);
  scales_.reserve(wanted);
  for (int level = 0; level < wanted; ++level) {
    const double scale = std::pow(options.scaleFactor, level - options.firstLevel);
    if (level == options.firstLevel) {
      images_.push_back(grey);
      scales_.push_back(1.0);
      continue;
    }
    // Sizes come from the input's size (not the previous level's) so rounding does not
    // accumulate; reductions take their pixels from the previous level, as cv::ORB does, and
    // enlargements from the input. INTER_LINEAR as cv::ORB: OpenCV's 8-bit bilinear in fixed
    // point (integer, whatever SIMD path runs it); INTER_LINEAR_EXACT took twice as long.
    // resize_kernels' (the same bits; BM_Pyramid 0.38x cv::resize's time at avx2, 0.62x at
    // sse4), except at the portable level, where OpenCV's own vectors take half the time of one
    // lane.
    const cv::Size size(static_cast<int>(std::lround(grey.cols / scale)),
                        static_cast<int>(std::lround(grey.rows / scale)));
    if (size.width < 1 || size.height < 1) break;  // nothing left to sample
    const cv::Mat& from = level < options.firstLevel ? grey : images_.back();
    cv::Mat level_image;
    if (activeSimdLevel() != SimdLevel::Portable) {
      level_image.create(size, CV_8UC1);
      resize_kernels::resizeLinear(from.data, from.step, from.cols, from.rows, level_image.data, level_image.step,
                                   size.width, size.height);
    } else {
      cv::resize(from, level_image, size, 0, 0, cv::INTER_LINEAR);
    }
    images_.push_back(level_image);
    scales_.push_back(scale);
  }
  smoothed_ = std::make_shared<SmoothedLevels>(images_.size());
}

LevelGrid ImagePyramid::grid(int level) const {
  const cv::Mat& image = images_.at(level);
  return {scales_[level], cv::Point2d(static_cast<double>(inputSize_.width) / image.cols,
                                      static_cast<double>(inputSize_.height) / image.rows)};
}

const cv::Mat& ImagePyramid::smoothedFloat(int level, double sigma) const {
  if (!(sigma > 0 && sigma <= kMaxFloatSigma))
    throw std::invalid_argument("ImagePyramid::smoothedFloat: sigma must be in (0, 8] level pixels, not " +
                                std::to_string(sigma));
  const cv::Mat& image = images_.at(level);
  const std::lock_guard<std::mutex> lock(smoothed_->floatMutex[level]);
  std::list<SmoothedLevels::FloatLevel>& made = smoothed_->floats[level];
  for (const SmoothedLevels::FloatLevel& f : made)
    if (f.sigma == sigma) return f.image;
  made.push_back({sigma, detail::gaussianSmoothing(image, detail::threeSigmaTaps(sigma), sigma, true).floats});
  return made.back().image;
}

const cv::Mat& ImagePyramid::smoothed(int level) const {
  cv::Mat& target = smoothed_->bytes.at(level);
  std::call_once(smoothed_->byteOnce[level], [&] {
    target = detail::gaussianSmoothing(images_[level], options_.smoothingKernel, options_.smoothingSigma, false).bytes;
  });
  return target;
}

const cv::Mat& ImagePyramid::smoothedPairs(int level) const {
  cv::Mat& target = smoothed_->pairs.at(level);
  std::call_once(smoothed_->pairOnce[level], [&] {
    const cv::Mat& bytes = smoothed(level);
    const auto pairRows = smoothing_kernels::activeSmoothingKernels().pairRows;
    target.create(bytes.size(), CV_8UC2);
    for (int y = 0; y < bytes.rows; ++y)
      pairRows(bytes.ptr(y), bytes.ptr(std::min(y + 1, bytes.rows - 1)), bytes.cols, target.ptr(y));
  });
  return target;
}

void ImagePyramid::adoptSmoothed(int level, const cv::Mat& bytes) const {
  std::call_once(smoothed_->byteOnce.at(level), [&] { smoothed_->bytes[level] = bytes; });
}

void ImagePyramid::prepareSmoothed(int maxLevel) const {
  // maxLevel is inclusive; a negative value or one past the last level prepares all levels.
  const int last = (maxLevel < 0 || maxLevel >= levels()) ? levels() - 1 : maxLevel;
  // Levels are independent: blur them in parallel (the blur costs about as much as the whole
  // description on one core).
  tbb::parallel_for(0, last + 1, [this](int level) { smoothed(level); });
}

}  // namespace mdbrief
