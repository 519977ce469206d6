#pragma once
// The Gaussian smoothing of an 8-bit pyramid level in integer arithmetic: what the descriptors
// sample (8 bits) and what the Hessian detector differentiates (float) are one result, the same
// on every CPU and at every SIMD level.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/smoothing_kernels.hpp"

namespace mdbrief::detail {

struct Smoothing {
  cv::Mat bytes;   // CV_8U: the smoothed level rounded to whole grey levels
  cv::Mat floats;  // CV_32F intensities in [0, 1], when asked for (else empty)
};

// Widest kernel, in taps: the Hessian detector's largest sigma (8) truncated at 3 sigma.
constexpr int kMaxSmoothingTaps = 49;

// The level smoothed by a `taps`-wide (odd, <= kMaxSmoothingTaps) Gaussian of `sigma`,
// separably: rows exactly with weights in 1/256, then columns with weights in 1/65536 rounded
// to 8 fractional bits, from which both forms are rounded. Borders reflect as
// BORDER_REFLECT_101. The weights are the Gaussian's rounded symmetrically, the centre taking
// what rounding leaves so that they sum to one exactly (a flat image stays flat); the rows'
// coarser weights halve the time, and keep the result within a grey level of the exact Gaussian.
Smoothing gaussianSmoothing(const cv::Mat& level8u, int taps, double sigma, bool withFloats);

// The same smoothing one output row at a time, top to bottom, for a consumer that uses each row
// while it is in the cache (the Hessian response) instead of writing a level-sized image and
// reading it back. The level must outlive the smoother.
class GaussianRowSmoother {
 public:
  // Throws std::invalid_argument for what gaussianSmoothing refuses.
  GaussianRowSmoother(const cv::Mat& level8u, int taps, double sigma);
  // The next row of both forms, from the top (cols bytes; cols floats unless floats is null).
  void next(uint8_t* bytes, float* floats);

 private:
  void smoothSourceRow(int s);

  cv::Mat level_;
  int rows_, cols_, radius_, window_;
  std::vector<uint32_t> rowWeights_, columnWeights_;
  // Row-smoothed rows in a ring of `window` slots (source row s in slot s % window): every row
  // an output row reads, reflections included, lies within `radius` rows of it, so the ring
  // stays in the L1 cache instead of a level-sized intermediate image.
  std::vector<uint16_t> ring_, padded_;
  // The reflected columns of the padding, and the ring slot of every row an output row reads
  // (-radius .. rows - 1 + radius, reflected), found once rather than per row and tap: output
  // row y reads slots_[y .. y + 2 radius].
  std::vector<int> leftColumn_, rightColumn_;
  std::vector<const uint16_t*> slots_;
  smoothing_kernels::SmoothingKernels kernels_;
  int smoothedRows_ = 0, y_ = 0;
};

}  // namespace mdbrief::detail
