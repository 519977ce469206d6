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
// The taps of a Gaussian of `sigma` truncated at 3 sigma: 2 ceil(3 sigma) + 1.
int threeSigmaTaps(double sigma);

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
  // It points into its own ring: a copy would read the original's.
  GaussianRowSmoother(const GaussianRowSmoother&) = delete;
  GaussianRowSmoother& operator=(const GaussianRowSmoother&) = delete;
  // The next row of both forms, from the top (cols bytes; cols floats unless floats is null).
  void next(uint8_t* bytes, float* floats);

 private:
  // The column pass's terms of an output row (smoothing_kernels.hpp): the weight of every row its
  // taps read, reflections folded in, by pair of rows; each pair an offset from the first pair
  // the row reads.
  struct RowTerms {
    int count = 0;
    int offsets[smoothing_kernels::kMaxTerms];
    uint32_t weights[smoothing_kernels::kMaxTerms];
  };
  // The terms of a row whose taps read rows read[0 .. 2 radius], from pair `first` on.
  RowTerms foldTerms(const int* read, int first) const;
  void smoothPair(int pair);

  cv::Mat level_;
  int rows_, cols_, radius_;
  std::vector<uint32_t> rowWeights_, columnWeights_;
  // Row-smoothed rows in pairs (rows 2 q and 2 q + 1 interleaved, pair q in slot q % (radius +
  // 1)): every row an output row reads, reflections included, lies within `radius` rows of it,
  // so the ring stays in the L1 cache instead of a level-sized intermediate image. slots_[i] is
  // slot i % (radius + 1), for i up to twice that, so that no term takes a modulo.
  std::vector<uint16_t> ring_, padded_;
  std::vector<const uint16_t*> slots_;
  // The reflected columns of the padding.
  std::vector<int> leftColumn_, rightColumn_;
  // The terms of every output row: rows whose taps reflect have their own, the others share one
  // of two by the parity of their first row.
  std::vector<RowTerms> terms_;
  std::vector<const RowTerms*> termsOfRow_;
  int termCount_ = 0;  // the most terms any output row takes; rows with fewer add zero weights
  std::vector<const uint16_t*> termPairs_;
  std::vector<uint32_t> termWeights_;
  smoothing_kernels::SmoothingKernels kernels_;
  int smoothedPairs_ = 0, y_ = 0;
};

// The same smoothing's float form at the 5x5 pixels around one pixel, for a level read at a few
// places only (the Hessian detector's finest level): gaussianSmoothing's values, and beyond the
// border the values BORDER_REFLECT_101 gives the smoothed level (the kernel is symmetric, so
// smoothing the reflected level reflects the smoothed one).
class GaussianBlockSmoother {
 public:
  // Throws std::invalid_argument for what gaussianSmoothing refuses. The level must outlive it.
  GaussianBlockSmoother(const cv::Mat& level8u, int taps, double sigma);
  // out[5 i + j]: the smoothed level at (cx - 2 + j, cy - 2 + i), for any cx and cy.
  void block(int cx, int cy, float* out) const;
  // Asks the cache for the pixels block(cx, cy) reads, ahead of the call.
  void prefetch(int cx, int cy) const;
  cv::Size levelSize() const { return level_.size(); }

 private:
  cv::Mat level_;
  int rows_, cols_, radius_;
  std::vector<uint32_t> rowWeights_, columnWeights_;
  smoothing_kernels::SmoothingKernels kernels_;
};

}  // namespace mdbrief::detail
