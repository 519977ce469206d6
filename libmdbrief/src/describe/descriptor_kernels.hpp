#pragma once
// Sampling kernels of the descriptor (descriptor.cpp), written once with Highway in
// descriptor_kernels.cpp and compiled for every SIMD level (simd_level.hpp); the scalar helpers
// below serve the vectors' tails and the nearest-pixel sampling. Every level gives the same bits.
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace mdbrief::descriptor_kernels {

// Sample positions are quantised to 1/32 pixel (cv::remap's INTER_BITS) and interpolated with
// integer weights: every form that computes the same position within 1e-9 px gets the same
// bits, which makes dBRIEF with a distortion-free pinhole equal BRIEF bit for bit.
constexpr int kSubBits = 5;
constexpr int kSub = 1 << kSubBits;
// The largest offset the affine placement takes (test sets and the orientation disc: 16).
constexpr int kMaxOffset = 16;

// The kernels of one SIMD level, resolved once per call.
struct SamplingKernels {
  // x[i] = toFixed(cx + m00 qa[i] + m01 qb[i]) and y[i] = toFixed(cy + m10 qa[i] + m11 qb[i])
  // for integer offsets |qa|, |qb| <= kMaxOffset, exactly as those double expressions round.
  void (*affinePoints)(double cx, double cy, double m00, double m01, double m10, double m11, const int32_t* qa,
                       const int32_t* qb, int n, int* x, int* y);
  // Bit d of out (d < nTests, a multiple of 32 as DescriptorOptions::bits) = bilinear sample
  // (x[d], y[d]) < sample (x[nTests + d], y[nTests + d]), read from the image's row pairs
  // (ImagePyramid::smoothedPairs: bytes 2 x and 2 x + 1 of pair row y are pixels (x, y) and
  // (x, y + 1), so a sample's four pixels are one 32-bit read). Every position inside the image
  // (descriptor.cpp allInside).
  void (*packBitsBilinear)(const uint8_t* pairs, size_t pairStep, const int* x, const int* y, int nTests,
                           uint8_t* out);
  // Whether every position can be sampled bilinearly in a width x height image (x0 + 1 <=
  // width - 1, y0 + 1 <= height - 1); nearest sampling reads a subset of those pixels.
  bool (*allInside)(const int* x, const int* y, int n, int width, int height);
  // Intensity moments sum(value * u), sum(value * v) of n bilinear samples (row pairs, as
  // packBitsBilinear).
  void (*centroidMoments)(const uint8_t* pairs, size_t pairStep, const int* x, const int* y, const int* u,
                          const int* v, int n, long long& m10, long long& m01);  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level (simd_level.hpp).
SamplingKernels activeSamplingKernels();

namespace {

inline int toFixed(double v) { return static_cast<int>(std::floor(v * kSub + 0.5)); }

inline int sampleBilinear(const uint8_t* data, size_t step, int px, int py) {
  const int fx = px & (kSub - 1), fy = py & (kSub - 1);
  const uint8_t* r0 = data + (py >> kSubBits) * step + (px >> kSubBits);
  const uint8_t* r1 = r0 + step;
  return (r0[0] * (kSub - fx) + r0[1] * fx) * (kSub - fy) + (r1[0] * (kSub - fx) + r1[1] * fx) * fy;
}

// sampleBilinear's value from the row pairs (packBitsBilinear).
inline int sampleBilinearPairs(const uint8_t* pairs, size_t pairStep, int px, int py) {
  const int fx = px & (kSub - 1), fy = py & (kSub - 1);
  const uint8_t* q = pairs + (py >> kSubBits) * pairStep + 2 * (px >> kSubBits);
  return (q[0] * (kSub - fx) + q[2] * fx) * (kSub - fy) + (q[1] * (kSub - fx) + q[3] * fx) * fy;
}

inline int sampleNearest(const uint8_t* data, size_t step, int px, int py) {
  return data[((py + kSub / 2) >> kSubBits) * step + ((px + kSub / 2) >> kSubBits)];
}

// Min/max in one pass.
inline bool allInsideImage(const int* x, const int* y, int n, int width, int height) {
  int minX = x[0], minY = y[0], maxX = x[0], maxY = y[0];
  for (int i = 1; i < n; ++i) {
    minX = x[i] < minX ? x[i] : minX, maxX = x[i] > maxX ? x[i] : maxX;
    minY = y[i] < minY ? y[i] : minY, maxY = y[i] > maxY ? y[i] : maxY;
  }
  return minX >= 0 && minY >= 0 && maxX < (width - 1) * kSub && maxY < (height - 1) * kSub;
}

}  // namespace
}  // namespace mdbrief::descriptor_kernels
