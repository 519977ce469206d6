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

Smoothing gaussianSmoothing(const cv::Mat& level8u, int taps, double sigma, bool withFloats) {
  if (level8u.type() != CV_8UC1 || level8u.empty())
    throw std::invalid_argument("gaussianSmoothing: needs a non-empty 8UC1 image");
  if (taps < 1 || taps % 2 == 0 || taps > kMaxSmoothingTaps || !(sigma > 0.0))
    throw std::invalid_argument("gaussianSmoothing: needs an odd width of at most 49 taps and a positive sigma");
  const int rows = level8u.rows, cols = level8u.cols, radius = taps / 2, window = taps;
  const std::vector<uint32_t> rowWeights = fixedWeights(taps, sigma, 8), columnWeights = fixedWeights(taps, sigma, 16);
  const smoothing_kernels::SmoothingKernels kernels = smoothing_kernels::activeSmoothingKernels();

  // Row-smoothed rows in a ring of `window` slots (source row s in slot s % window): every row
  // an output row reads, reflections included, lies within `radius` rows of it, so the ring
  // stays in the L1 cache instead of a level-sized intermediate image.
  std::vector<uint16_t> ring(static_cast<size_t>(window) * cols), padded(cols + 2 * radius);
  // The reflected columns of the padding, found once rather than per row.
  std::vector<int> leftColumn(radius + 1), rightColumn(radius + 1);
  for (int i = 1; i <= radius; ++i) {
    leftColumn[i] = cv::borderInterpolate(-i, cols, cv::BORDER_REFLECT_101);
    rightColumn[i] = cv::borderInterpolate(cols - 1 + i, cols, cv::BORDER_REFLECT_101);
  }
  const auto smoothSourceRow = [&](int s) {
    const uint8_t* in = level8u.ptr<uint8_t>(s);
    std::copy(in, in + cols, padded.begin() + radius);
    for (int i = 1; i <= radius; ++i) {
      padded[radius - i] = in[leftColumn[i]];
      padded[radius + cols - 1 + i] = in[rightColumn[i]];
    }
    kernels.rows(padded.data() + radius, cols, rowWeights.data(), radius, &ring[static_cast<size_t>(s % window) * cols]);
  };
  Smoothing out{cv::Mat(rows, cols, CV_8U), withFloats ? cv::Mat(rows, cols, CV_32F) : cv::Mat()};
  std::vector<const uint16_t*> taken(window);
  // The source row of every row an output row reads (-radius .. rows - 1 + radius), reflected
  // once here rather than per output row and tap.
  std::vector<int> source(rows + 2 * radius);
  for (int i = 0; i < rows + 2 * radius; ++i) source[i] = cv::borderInterpolate(i - radius, rows, cv::BORDER_REFLECT_101);
  int smoothedRows = 0;
  for (int y = 0; y < rows; ++y) {
    for (; smoothedRows < rows && smoothedRows <= y + radius; ++smoothedRows) smoothSourceRow(smoothedRows);
    for (int k = -radius; k <= radius; ++k)
      taken[radius + k] = &ring[static_cast<size_t>(source[y + k + radius] % window) * cols];
    kernels.columns(taken.data(), cols, columnWeights.data(), radius, out.bytes.ptr<uint8_t>(y),
                    withFloats ? out.floats.ptr<float>(y) : nullptr);
  }
  return out;
}

}  // namespace detail
}  // namespace mdbrief
