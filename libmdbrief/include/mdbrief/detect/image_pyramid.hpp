#pragma once
// ORB-style scale pyramid shared by the detector and the descriptors. Level k is the input
// resampled by 1 / scale(k), scale(k) = scaleFactor^(k - firstLevel) (as cv::ORB): levels above
// firstLevel are bilinear reductions of the level before, levels below it enlarge the input.
// Keypoint coordinates are always input pixels; LevelGrid maps them to level coordinates.
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {
class Detector;

struct PyramidOptions {
  int levels = 8;               // number of levels (cv::ORB default)
  double scaleFactor = 1.2;     // ratio between neighbouring levels (cv::ORB default)
  // Level holding the input image (cv::ORB's firstLevel); levels below it are upsampled, which
  // finds smaller features at the price of larger images. 0..levels-1.
  int firstLevel = 0;
  // Descriptor smoothing, as ORB/BRIEF: Gaussian 7x7, sigma 2, applied per level.
  int smoothingKernel = 7;
  double smoothingSigma = 2.0;
};

// The fields of PyramidOptions (option_fields.hpp): names, docs and accepted values.
const OptionTable<PyramidOptions>& pyramidOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const PyramidOptions& options);

// Where a level's pixels lie in the input. cv::resize aligns pixel centres, so level pixel x is
// input pixel (x + 0.5) * step - 0.5, step = input size / level size along each axis (the rounded
// sizes): pt / scale would misplace a coarse level's keypoints by half a level pixel and more
// (several input pixels), and matches across levels by the difference.
struct LevelGrid {
  double scale = 1.0;      // the level's nominal scale: sizes
  cv::Point2d step{1, 1};  // input pixels per level pixel, per axis: positions
  cv::Point2d toInput(const cv::Point2d& level) const {
    return {(level.x + 0.5) * step.x - 0.5, (level.y + 0.5) * step.y - 0.5};
  }
  cv::Point2d toLevel(const cv::Point2d& input) const {
    return {(input.x + 0.5) / step.x - 0.5, (input.y + 0.5) / step.y - 0.5};
  }
  // Offsets in nominal level pixels (input pixels / scale) to the level's own, which differ by
  // the rounding of its size: a footprint stays supportScale * size input pixels on both axes.
  cv::Matx22d fromNominal() const { return {scale / step.x, 0.0, 0.0, scale / step.y}; }
};

class ImagePyramid {
 public:
  ImagePyramid() = default;
  // image: 8UC1 (8UC3/8UC4 are converted to grey). Throws std::invalid_argument if empty or of
  // another type. Only levels < maxLevels are built (all when maxLevels < 0).
  ImagePyramid(const cv::Mat& image, const PyramidOptions& options, int maxLevels = -1);

  int levels() const { return static_cast<int>(images_.size()); }
  // Size of the input image (level firstLevel), the frame of keypoint coordinates.
  cv::Size inputSize() const { return inputSize_; }
  double scale(int level) const { return scales_.at(level); }
  LevelGrid grid(int level) const;
  const PyramidOptions& options() const { return options_; }
  const cv::Mat& image(int level) const { return images_.at(level); }
  // The level smoothed by the options' Gaussian, rounded to 8 bits: what the descriptors sample,
  // and the Hessian detector's response smooths alike (the two share one blur). Made once, on
  // first use: safe to call from several threads, and a detector that does not need it never pays
  // for it. prepareSmoothed() makes the levels 0..maxLevel (all if negative) in parallel ahead of
  // parallel sampling.
  const cv::Mat& smoothed(int level) const;
  void prepareSmoothed(int maxLevel) const;
  // The level smoothed by a Gaussian of `sigma` level pixels, 3 sigma wide, as CV_32F intensities
  // in [0, 1]: the integer smoothing of smoothed(), so identical on every CPU. What sub-pixel
  // alignment reads (match_refinement.hpp), which wants less smoothing than the descriptors.
  // Made once per level and sigma, on first use; safe to call from several threads. Throws
  // std::invalid_argument unless sigma is in (0, kMaxFloatSigma].
  static constexpr double kMaxFloatSigma = 8.0;
  const cv::Mat& smoothedFloat(int level, double sigma) const;
  // The 8-bit smoothed level as the descriptors' bilinear sampling reads it (CV_8UC2, the level's
  // size): pixel (x, y) holds smoothed (x, y) and (x, y + 1), the last row itself twice, so that
  // a sample's four pixels are four consecutive bytes. Made once, on first use, as smoothed().
  const cv::Mat& smoothedPairs(int level) const;

 private:
  // The smoothed forms of every level, made on first use (image_pyramid.cpp); shared by copies
  // of the pyramid, whose levels are the same images.
  struct SmoothedLevels;
  // The Hessian detector smooths each level by the options' Gaussian on its way to the response:
  // it hands the bytes over instead of the level being smoothed twice.
  friend class Detector;
  void adoptSmoothed(int level, const cv::Mat& bytes) const;

  PyramidOptions options_;
  cv::Size inputSize_;
  std::vector<cv::Mat> images_;
  std::vector<double> scales_;
  std::shared_ptr<SmoothedLevels> smoothed_;
};

// Converts 8UC1/8UC3/8UC4 to an 8UC1 grey image (no copy for 8UC1). Throws
// std::invalid_argument naming the type otherwise, or if the image is empty.
cv::Mat toGrey(const cv::Mat& image);

}  // namespace mdbrief
