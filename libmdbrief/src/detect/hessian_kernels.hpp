#pragma once
// The Hessian detector's per-pixel loops (detect/hessian.cpp), written once with Highway in
// hessian_kernels.cpp and compiled for every SIMD level (simd_level.hpp). Each lane does the
// scalar form's operations in the same order, rounded one at a time (no fused multiply-add), so
// every level gives the same bits.
#include <cstdint>

namespace mdbrief::hessian_kernels {

constexpr int kMaxBlockTaps = 49;
// gaussianBlock5's vectors: 8 lanes at most, which cover the block's 5 columns along its rows
// once (the columns pass reads as many more as the taps).
constexpr int kBlockLanes = 8;
constexpr int blockReadWidth(int taps) { return kBlockLanes + ((taps - 1 + kBlockLanes - 1) & ~(kBlockLanes - 1)); }

struct HessianKernels {
  // Columns 1 .. cols - 2 of one row of the response: with a, b, c the rows above, at and below,
  // dxx = (b[x-1] + b[x+1]) - 2 b[x], dyy = (a[x] + c[x]) - 2 b[x],
  // dxy = ((c[x+1] - c[x-1]) - (a[x+1] - a[x-1])) / 4 and out[x] = (dxx dyy - dxy^2) scale.
  void (*responseRow)(const float* a, const float* b, const float* c, int cols, float scale, float* out);
  // out[x] = max(row[x - 1], row[x], row[x + 1]) for the columns 1 .. cols - 2.
  void (*rowMax3)(const float* row, int cols, float* out);
  // The columns x in [begin, end) where row[x] > threshold and row[x] is at least each of its
  // eight neighbours, in increasing order, into xs (room for end - begin + 8 entries: whole
  // vectors are stored there, of which the count returned are the candidates); maxAbove,
  // maxRow and maxBelow are rowMax3 of the rows above, at and below. Returns how many.
  int (*candidates)(const float* row, const float* maxAbove, const float* maxRow, const float* maxBelow, int begin,
                    int end, float threshold, int32_t* xs);
  // The Gaussian smoothing at a 5x5 block of pixels, for blob_localisation.cpp. Down the columns
  // first, v[i][c] = sum over t of weights[t] rows[i + t][c] for the block's rows i < 5, then along
  // its rows, out[5 i + j] = sum over t of weights[t] v[i][j + t]; each sum over t = 0 .. taps - 1
  // in that order from 0. taps <= kMaxBlockTaps; rows[0 .. taps + 3] are readable for
  // blockReadWidth(taps) bytes, of which the first taps + 4 are the block's columns.
  void (*gaussianBlock5)(const uint8_t* const* rows, int taps, const float* weights, float* out);
  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level.
HessianKernels activeHessianKernels();

}  // namespace mdbrief::hessian_kernels
