#pragma once
// The two passes of the pyramid's fixed-point Gaussian (gaussian_smoothing.cpp) and the layout of
// its bytes for the descriptors' sampling (image_pyramid.cpp), written once
// with Highway in smoothing_kernels.cpp and compiled for every SIMD level (simd_level.hpp). The
// arithmetic is integer, so every level gives the same values.
#include <cstdint>

namespace mdbrief::smoothing_kernels {

constexpr int kMaxRadius = 24;  // gaussian_smoothing.hpp kMaxSmoothingTaps

// Most terms a column pass may take: one per pair of rows within the radius, and two more for
// the weights above 32767 split in parts (at most 65536 in all, so at most two such rows).
constexpr int kMaxTerms = kMaxRadius + 3;

// The float form's unit: the column pass's sums (8 fractional bits) to intensities in [0, 1].
constexpr float kFixedToUnit = 1.f / (256.f * 255.f);

struct SmoothingKernels {
  // out[x] = in[x] for x < n: a row widened for rowPair.
  void (*widen)(const uint8_t* in, int n, uint16_t* out);
  // Two rows at once. radius <= kMaxRadius; upper[-radius .. cols - 1 + radius] and lower's
  // readable. With weights w[0..radius] in 1/256, of 8-bit pixels (widened to 16 bits): the
  // row-smoothed value of upper at x, sum over |k| <= radius of w[|k|] * upper[x + k], is 256 x
  // the row-smoothed intensity exactly (at most 255 x 256: 16-bit lanes, twice as many as 32-bit
  // ones). out[2 x] is it less 32768 (so that it fits a signed 16-bit lane) and out[2 x + 1]
  // lower's: a pair of rows as the column pass reads them.
  void (*rowPair)(const uint16_t* upper, const uint16_t* lower, int cols, const uint32_t* w, int radius,
                  uint16_t* out);
  // The column pass over 1 <= terms <= kMaxTerms pairs of rows (rowPair's layout). Term t
  // weighs pairs[t]'s upper row by weights[t] & 0xffff and its lower one by weights[t] >> 16, in
  // 1/65536, each at most 32767 and all summing to at most 65536 (a row within the radius twice,
  // or with a larger weight, takes several terms). The weighted sum of the row-smoothed values /
  // 65536, rounded, is 256 x the smoothed intensity, in 8 fractional bits; bytes[x] is it
  // rounded to a whole grey level and, unless floats is null, floats[x] it / (256 x 255).
  void (*columns)(const uint16_t* const* pairs, const uint32_t* weights, int terms, int cols, uint8_t* bytes,
                  float* floats);
  // Two rows of the smoothed bytes side by side, as the descriptors sample them
  // (ImagePyramid::smoothedPairs): out[2 x] = upper[x], out[2 x + 1] = lower[x].
  void (*pairRows)(const uint8_t* upper, const uint8_t* lower, int cols, uint8_t* out);
  // The same smoothing at a 5x5 block of pixels only, for a level read at a few places: both
  // passes are exact integer sums, so in any order they give the column pass's rounded values.
  // rows[t], t < 2 radius + 5, is the block's row t - radius - 2 from its first column less
  // radius + 2, readable for 2 radius + kBlockSlack bytes; w the row pass's weights, columnWeights
  // the column pass's (w[0..radius] each, 1/256 and 1/65536, summing to one). out[5 i + j] is
  // row i, column j of the block in 8 fractional bits, as `columns` computes before rounding.
  void (*block5)(const uint8_t* const* rows, int radius, const uint32_t* w, const uint32_t* columnWeights,
                 uint32_t* out);  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// Bytes a block5 row is read for beyond the block's 2 radius + 5: its vectors cover 8 columns.
constexpr int kBlockSlack = 8;

// The kernels of the active SIMD level.
SmoothingKernels activeSmoothingKernels();

}  // namespace mdbrief::smoothing_kernels
