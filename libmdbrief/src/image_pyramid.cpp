#include "mdbrief/image_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

namespace mdbrief {

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
    // enlargements from the input.
    const cv::Size size(static_cast<int>(std::lround(grey.cols / scale)),
                        static_cast<int>(std::lround(grey.rows / scale)));
    if (size.width < 1 || size.height < 1) break;  // nothing left to sample
    cv::Mat level_image;
    if (level < options.firstLevel)
      cv::resize(grey, level_image, size, 0, 0, cv::INTER_LINEAR_EXACT);
    else
      cv::resize(images_.back(), level_image, size, 0, 0, cv::INTER_LINEAR_EXACT);
    images_.push_back(level_image);
    scales_.push_back(scale);
  }
  smoothed_ = std::make_shared<SmoothedLevels>(images_.size());
}

const cv::Mat& ImagePyramid::smoothedFloat(int level) const {
  const cv::Mat& source = images_.at(level);
  cv::Mat& target = smoothed_->floats[level];
  std::call_once(smoothed_->floatOnce[level], [&] {
    // From the 8-bit level straight into float intensities: one pass fewer than converting first.
    const cv::Mat kernel = cv::getGaussianKernel(options_.smoothingKernel, options_.smoothingSigma, CV_32F);
    cv::sepFilter2D(source, target, CV_32F, kernel / 255.0, kernel, cv::Point(-1, -1), 0, cv::BORDER_REFLECT_101);
  });
  return target;
}

const cv::Mat& ImagePyramid::smoothed(int level) const {
  cv::Mat& target = smoothed_->bytes.at(level);
  std::call_once(smoothed_->byteOnce[level], [&] { smoothedFloat(level).convertTo(target, CV_8U, 255.0); });
  return target;
}

void ImagePyramid::prepareSmoothed(int maxLevel) const {
  // maxLevel is inclusive; a negative value or one past the last level prepares all levels.
  const int last = (maxLevel < 0 || maxLevel >= levels()) ? levels() - 1 : maxLevel;
  // Levels are independent: blur them in parallel (the blur costs about as much as the whole
  // description on one core).
  tbb::parallel_for(0, last + 1, [this](int level) { smoothed(level); });
}

}  // namespace mdbrief
