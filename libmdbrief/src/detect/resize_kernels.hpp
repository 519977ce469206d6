#pragma once
// The pyramid's bilinear resizing (image_pyramid.cpp), written once with Highway in
// resize_kernels.cpp and compiled for every SIMD level (simd_level.hpp): the bits of OpenCV
// 4.6's cv::resize(INTER_LINEAR) on 8-bit grey images, whose fixed point this reproduces. The
// arithmetic is integer, so every level gives the same values.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mdbrief::resize_kernels {

// OpenCV's weights are in 1/2048 (11 bits); the horizontal pass keeps each sum / 16, as OpenCV's
// vertical pass takes it.
constexpr int kWeightOne = 2048;

// Where each output column of a level takes its pixels: source columns first[x] and second[x]
// (the next one, or the same at the last column) weighted a0[x] and a1[x]. For the vector pass,
// each weight split as a = 16 high + low, and blocks of 8 columns (8 b .. 8 b + 7; the last
// block, when 8 does not divide cols, the last 8 columns) whose pixels lie in 16 bytes from
// window[b]: byte firstIndex[16 b + 2 i] of the window is column i's first pixel (the next
// byte 0x80: zero, the pixel widened to 16 bits), secondIndex its second. run[b] counts the
// blocks of consecutive columns from b on that fit their windows (0: b does not).
struct ColumnPlan {
  int srcCols = 0, cols = 0;
  std::vector<int32_t> first, second;
  std::vector<int16_t> a0, a1, high0, low0, high1, low1;
  std::vector<int32_t> window, run;
  std::vector<uint8_t> firstIndex, secondIndex;
};

struct ResizeKernels {
  // out[x] = (src[first] a0 + src[second] a1) / 16, rounded down (at most 255 x 2049 / 16).
  void (*columns)(const uint8_t* src, const ColumnPlan& plan, int16_t* out);
  // out[x] = ((upper[x] b0) / 2^16 + (lower[x] b1) / 2^16 + 2) / 4, each division rounded down.
  void (*rows)(const int16_t* upper, const int16_t* lower, int16_t b0, int16_t b1, int cols, uint8_t* out);
  // halveImage's horizontal pass, out[i] = p[2i - 2] + 4 p[2i - 1] + 6 p[2i] + 4 p[2i + 1] + p[2i + 2]
  // for i in [from, to), p the source row, whose pixels 2 from - 2 to 2 to + 1 it reads.
  void (*halveColumns)(const uint8_t* src, int from, int to, uint16_t* out);
  // halveImage's vertical pass, out[x] = (r0 + 4 r1 + 6 r2 + 4 r3 + r4 + 128) / 256 (rounded down)
  // of the horizontal rows r: at most 16 x 4080 + 128, 16 bits.
  void (*halveRows)(const uint16_t* const* rows, int cols, uint8_t* out);
  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level.
ResizeKernels activeResizeKernels();

// cv::resize(src, dst, {dstCols, dstRows}, 0, 0, INTER_LINEAR), reductions and enlargements, for
// sizes of at least one pixel; rows `stride` bytes apart. (At exactly half the size along both
// axes OpenCV takes INTER_AREA instead, whose value, the mean of four pixels rounded half up, is
// this arithmetic's at weights of one half.)
void resizeLinear(const uint8_t* src, size_t srcStride, int srcCols, int srcRows, uint8_t* dst, size_t dstStride,
                  int dstCols, int dstRows);

// cv::pyrDown(src, dst) on 8-bit grey images, its bits: the 5 x 5 binomial kernel (1 4 6 4 1)^2 /
// 256 rounded half up at every second pixel, borders reflected (BORDER_REFLECT_101), into
// (srcCols + 1) / 2 x (srcRows + 1) / 2 pixels. Sizes of at least one pixel.
void halveImage(const uint8_t* src, size_t srcStride, int srcCols, int srcRows, uint8_t* dst, size_t dstStride);

}  // namespace mdbrief::resize_kernels
