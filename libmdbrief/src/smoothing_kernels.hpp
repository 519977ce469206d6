#pragma once
// The two passes of the pyramid's fixed-point Gaussian (gaussian_smoothing.cpp). The loops are
// written once, here, and compiled for three SIMD levels by the compiler's vectoriser: the
// baseline in gaussian_smoothing.cpp, AVX2 and AVX-512 in x86/smoothing_kernel_avx2.cpp and
// x86/smoothing_kernel_avx512.cpp, chosen at run time (simd_level.hpp). The arithmetic is
// integer, so every level gives the same values. Internal linkage, as descriptor_kernels.hpp.
#include <cstdint>
#include <utility>

namespace mdbrief::smoothing_kernels {

struct SmoothingKernels {
  // radius <= kMaxRadius. With weights w[0..radius] in 1/256, of 8-bit pixels (widened to 16
  // bits): out[x] = sum over |k| <= radius of w[|k|] * centre[x + k], 256 x the row-smoothed
  // intensity, exactly (at most 255 x 256: 16-bit lanes, twice as many as 32-bit ones).
  void (*rows)(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out);
  // With weights in 1/65536, over the row-smoothed rows rows[0..2 radius] (rows[radius] the centre): the
  // weighted sum / 65536, rounded, is 256 x the smoothed intensity, in 8 fractional bits;
  // bytes[x] is it rounded to a whole grey level and, unless floats is null, floats[x] it / (256 x 255).
  void (*columns)(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes,
                  float* floats);
};

SmoothingKernels portableSmoothingKernels();
SmoothingKernels avx2SmoothingKernels();
SmoothingKernels avx512SmoothingKernels();
// The kernels of the active SIMD level.
SmoothingKernels activeSmoothingKernels();

namespace {

constexpr int kMaxRadius = 24;  // gaussian_smoothing.hpp kMaxSmoothingTaps

// The radius is a template parameter so that the taps unroll and every sum stays in a register;
// the loops run over contiguous columns in types no wider than the sums need (rows: 16 bits;
// columns: at most 65280 x 65536 with the rounding, below 2^32), which the vectoriser turns
// into full-width integer lanes.
template <int R>
void smoothRowR(const uint16_t* centre, int cols, const uint32_t* w, uint16_t* __restrict out) {
  uint16_t wk[R + 1];
  for (int k = 0; k <= R; ++k) wk[k] = static_cast<uint16_t>(w[k]);
  for (int x = 0; x < cols; ++x) {
    uint16_t sum = static_cast<uint16_t>(wk[0] * centre[x]);
    for (int k = 1; k <= R; ++k) sum = static_cast<uint16_t>(sum + wk[k] * (centre[x - k] + centre[x + k]));
    out[x] = sum;
  }
}

template <int R, bool Floats>
void smoothColumnsR(const uint16_t* const* rows, int cols, const uint32_t* w, uint8_t* __restrict bytes,
                    float* __restrict floats) {
  const uint16_t* r[2 * R + 1];
  uint32_t wk[R + 1];
  for (int k = 0; k <= 2 * R; ++k) r[k] = rows[k];
  for (int k = 0; k <= R; ++k) wk[k] = w[k];
  for (int x = 0; x < cols; ++x) {
    uint32_t sum = wk[0] * r[R][x];
    for (int k = 1; k <= R; ++k) sum += wk[k] * (uint32_t{r[R - k][x]} + r[R + k][x]);
    const uint32_t fixed = (sum + (1u << 15)) >> 16;  // 256 x the smoothed intensity
    bytes[x] = static_cast<uint8_t>((fixed + 128u) >> 8);
    if constexpr (Floats) floats[x] = static_cast<float>(static_cast<int>(fixed)) * (1.f / (256.f * 255.f));
  }
}

template <int... R>
void smoothRowDispatch(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out,
                       std::integer_sequence<int, R...>) {
  using Row = void (*)(const uint16_t*, int, const uint32_t*, uint16_t*);
  static constexpr Row forRadius[] = {smoothRowR<R>...};
  forRadius[radius](centre, cols, w, out);
}

template <int... R>
void smoothColumnsDispatch(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes,
                           float* floats, std::integer_sequence<int, R...>) {
  using Columns = void (*)(const uint16_t* const*, int, const uint32_t*, uint8_t*, float*);
  static constexpr Columns bytesOnly[] = {smoothColumnsR<R, false>...};
  static constexpr Columns withFloats[] = {smoothColumnsR<R, true>...};
  (floats ? withFloats : bytesOnly)[radius](rows, cols, w, bytes, floats);
}

inline void smoothRow(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out) {
  smoothRowDispatch(centre, cols, w, radius, out, std::make_integer_sequence<int, kMaxRadius + 1>());
}

inline void smoothColumns(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes,
                          float* floats) {
  smoothColumnsDispatch(rows, cols, w, radius, bytes, floats, std::make_integer_sequence<int, kMaxRadius + 1>());
}

}  // namespace
}  // namespace mdbrief::smoothing_kernels
