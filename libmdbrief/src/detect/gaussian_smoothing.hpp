#pragma once
// The Gaussian smoothing of an 8-bit pyramid level in integer arithmetic: what the descriptors
// sample (8 bits) and what the Hessian detector differentiates (float) are one result, the same
// on every CPU and at every SIMD level.
#include <opencv2/core.hpp>

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

}  // namespace mdbrief::detail
