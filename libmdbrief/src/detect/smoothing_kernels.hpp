#pragma once
// The two passes of the pyramid's fixed-point Gaussian (gaussian_smoothing.cpp) and the layout of
// its bytes for the descriptors' sampling (image_pyramid.cpp), written once
// with Highway in smoothing_kernels.cpp and compiled for every SIMD level (simd_level.hpp). The
// arithmetic is integer, so every level gives the same values.
#include <cstdint>

namespace mdbrief::smoothing_kernels {

constexpr int kMaxRadius = 24;  // gaussian_smoothing.hpp kMaxSmoothingTaps

struct SmoothingKernels {
  // radius <= kMaxRadius; centre[-radius .. cols - 1 + radius] readable. With weights
  // w[0..radius] in 1/256, of 8-bit pixels (widened to 16 bits): out[x] = sum over |k| <= radius
  // of w[|k|] * centre[x + k], 256 x the row-smoothed intensity, exactly (at most 255 x 256:
  // 16-bit lanes, twice as many as 32-bit ones).
  void (*rows)(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out);
  // With weights in 1/65536, over the row-smoothed rows rows[0..2 radius] (rows[radius] the
  // centre): the weighted sum / 65536, rounded, is 256 x the smoothed intensity, in 8
  // fractional bits; bytes[x] is it rounded to a whole grey level and, unless floats is null,
  // floats[x] it / (256 x 255).
  void (*columns)(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes,
                  float* floats);
  // Two rows of the smoothed bytes side by side, as the descriptors sample them
  // (ImagePyramid::smoothedPairs): out[2 x] = upper[x], out[2 x + 1] = lower[x].
  void (*pairRows)(const uint8_t* upper, const uint8_t* lower, int cols, uint8_t* out);
};

// The kernels of the active SIMD level.
SmoothingKernels activeSmoothingKernels();

}  // namespace mdbrief::smoothing_kernels
