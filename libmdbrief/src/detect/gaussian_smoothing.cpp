#include "detect/gaussian_smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "detect/smoothing_kernels.hpp"

namespace mdbrief {

namespace detail {
namespace {

static_assert(2 * smoothing_kernels::kMaxRadius + 1 == kMaxSmoothingTaps);

// The Gaussian's weights for offsets 0..radius (symmetric) in units of 2^-bits: each its scaled
// value rounded down or up, the largest remainders rounded up, so that they sum to one exactly
// and none is negative however coarse the units are against the kernel.
std::vector<uint32_t> fixedWeights(int taps, double sigma, int bits) {
  const int radius = taps / 2;
  const cv::Mat g = cv::getGaussianKernel(taps, sigma, CV_64F);
  std::vector<uint32_t> w(radius + 1);
  std::vector<std::pair<double, int>> remainders;  // (fraction, offset) of the side weights
  int64_t left = int64_t{1} << bits;
  for (int k = 0; k <= radius; ++k) {
    const double scaled = std::ldexp(g.at<double>(radius + k), bits);
    w[k] = static_cast<uint32_t>(std::floor(scaled));
    left -= (k == 0 ? 1 : 2) * int64_t{w[k]};
    if (k > 0) remainders.emplace_back(scaled - w[k], k);
  }
  // A side weight counts twice, so the centre takes an odd unit; the fractions sum below
  // taps, so the sides' units never outnumber them.
  if (left % 2 != 0) ++w[0], --left;
  std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (size_t i = 0; left > 0 && i < remainders.size(); ++i, left -= 2) ++w[remainders[i].second];
  return w;
}

}  // namespace

GaussianRowSmoother::GaussianRowSmoother(const cv::Mat& level8u, int taps, double sigma) : level_(level8u) {
  if (level8u.type() != CV_8UC1 || level8u.empty())
    throw std::invalid_argument("gaussianSmoothing: needs a non-empty 8UC1 image");
  if (taps < 1 || taps % 2 == 0 || taps > kMaxSmoothingTaps || !(sigma > 0.0))
    throw std::invalid_argument("gaussianSmoothing: needs an odd width of at most 49 taps and a positive sigma");
  rows_ = level8u.rows, cols_ = level8u.cols, radius_ = taps / 2, window_ = taps;
  rowWeights_ = fixedWeights(taps, sigma, 8), columnWeights_ = fixedWeights(taps, sigma, 16);
  ring_.resize(static_cast<size_t>(window_) * cols_);
  padded_.resize(cols_ + 2 * radius_);
  leftColumn_.resize(radius_ + 1), rightColumn_.resize(radius_ + 1);
  for (int i = 1; i <= radius_; ++i) {
    leftColumn_[i] = cv::borderInterpolate(-i, cols_, cv::BORDER_REFLECT_101);
    rightColumn_[i] = cv::borderInterpolate(cols_ - 1 + i, cols_, cv::BORDER_REFLECT_101);
  }
  slots_.resize(rows_ + 2 * radius_);
  for (int i = 0; i < rows_ + 2 * radius_; ++i)
    slots_[i] = &ring_[static_cast<size_t>(cv::borderInterpolate(i - radius_, rows_, cv::BORDER_REFLECT_101) % window_) *
                       cols_];
  kernels_ = smoothing_kernels::activeSmoothingKernels();
}

void GaussianRowSmoother::smoothSourceRow(int s) {
  const uint8_t* in = level_.ptr<uint8_t>(s);
  std::copy(in, in + cols_, padded_.begin() + radius_);
  for (int i = 1; i <= radius_; ++i) {
    padded_[radius_ - i] = in[leftColumn_[i]];
    padded_[radius_ + cols_ - 1 + i] = in[rightColumn_[i]];
  }
  kernels_.rows(padded_.data() + radius_, cols_, rowWeights_.data(), radius_, &ring_[static_cast<size_t>(s % window_) * cols_]);
}

void GaussianRowSmoother::next(uint8_t* bytes, float* floats) {
  if (y_ >= rows_) throw std::out_of_range("GaussianRowSmoother::next: past the last row");
  for (; smoothedRows_ < rows_ && smoothedRows_ <= y_ + radius_; ++smoothedRows_) smoothSourceRow(smoothedRows_);
  kernels_.columns(&slots_[y_], cols_, columnWeights_.data(), radius_, bytes, floats);
  ++y_;
}

Smoothing gaussianSmoothing(const cv::Mat& level8u, int taps, double sigma, bool withFloats) {
  GaussianRowSmoother smoother(level8u, taps, sigma);
  Smoothing out{cv::Mat(level8u.rows, level8u.cols, CV_8U),
                withFloats ? cv::Mat(level8u.rows, level8u.cols, CV_32F) : cv::Mat()};
  for (int y = 0; y < level8u.rows; ++y)
    smoother.next(out.bytes.ptr<uint8_t>(y), withFloats ? out.floats.ptr<float>(y) : nullptr);
  return out;
}

}  // namespace detail
}  // namespace mdbrief
