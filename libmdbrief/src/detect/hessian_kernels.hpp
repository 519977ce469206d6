#pragma once
// The Hessian detector's per-pixel loops (detect/hessian.cpp), written once with Highway in
// hessian_kernels.cpp and compiled for every SIMD level (simd_level.hpp). Each lane does the
// scalar form's operations in the same order, rounded one at a time (no fused multiply-add), so
// every level gives the same bits.
#include <cstdint>

namespace mdbrief::hessian_kernels {

struct HessianKernels {
  // Columns 1 .. cols - 2 of one row of the response: with a, b, c the rows above, at and below,
  // dxx = (b[x-1] + b[x+1]) - 2 b[x], dyy = (a[x] + c[x]) - 2 b[x],
  // dxy = ((c[x+1] - c[x-1]) - (a[x+1] - a[x-1])) / 4 and out[x] = (dxx dyy - dxy^2) scale.
  void (*responseRow)(const float* a, const float* b, const float* c, int cols, float scale, float* out);
  // out[x] = max(row[x - 1], row[x], row[x + 1]) for the columns 1 .. cols - 2.
  void (*rowMax3)(const float* row, int cols, float* out);
  // The columns x in [begin, end) where row[x] > threshold and row[x] is at least each of its
  // eight neighbours, in increasing order, into xs (room for end - begin entries); maxAbove,
  // maxRow and maxBelow are rowMax3 of the rows above, at and below. Returns how many.
  int (*candidates)(const float* row, const float* maxAbove, const float* maxRow, const float* maxBelow, int begin,
                    int end, float threshold, int32_t* xs);
  // Gaussian passes for blob_localisation.cpp, each sum over t = 0 .. taps - 1 in that order from
  // 0, for c in [0, width): over rows of 8-bit pixels, out[c] = sum of weights[t] rows[t][c];
  // along a row, out[c] = sum of weights[t] row[c + t].
  void (*weightedRows)(const uint8_t* const* rows, int taps, const float* weights, int width, float* out);
  void (*weightedRow)(const float* row, int taps, const float* weights, int width, float* out);
  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level.
HessianKernels activeHessianKernels();

}  // namespace mdbrief::hessian_kernels
