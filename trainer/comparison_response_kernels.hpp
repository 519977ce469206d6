#pragma once
// Kernels of the comparison-response evaluation (patch_lanes.hpp, comparison_responses.cpp) for
// every SIMD level (mdbrief/base/simd_level.hpp), written once in comparison_response_kernels.cpp.
#include <cstddef>
#include <cstdint>

namespace mdbrief::train::kernels {

// 64 patches (one result word) sit side by side in 64 bytes, one byte per patch, so a test on
// 64 patches is one comparison of two 64-byte rows. A pixel's row holds consecutive words.
constexpr size_t kLanes = 64;

struct ResponseKernels {
  // column[w] = bit k set where byte k of word w of row a < that of row b (unsigned), w < words.
  void (*lessMasks)(const uint8_t* a, const uint8_t* b, size_t words, uint64_t* column);
  // Set bits of those masks.
  uint32_t (*ones)(const uint8_t* a, const uint8_t* b, size_t words);
  // Lanes where the test differs between two sets of patches: (a1 < a2) != (b1 < b2).
  uint32_t (*flips)(const uint8_t* a1, const uint8_t* a2, const uint8_t* b1, const uint8_t* b2, size_t words);
  // Set bits of x[i], of x[i] ^ y[i] and of x[i] & y[i], i < n.
  size_t (*popcount)(const uint64_t* x, size_t n);
  size_t (*popcountXor)(const uint64_t* x, const uint64_t* y, size_t n);
  size_t (*popcountAnd)(const uint64_t* x, const uint64_t* y, size_t n);  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level (comparison_response_kernels.cpp, written once with Highway and
// compiled for every level); callers resolve them once per call (or object).
ResponseKernels activeResponseKernels();

}  // namespace mdbrief::train::kernels
