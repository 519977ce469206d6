#pragma once
// Kernels of the test-response evaluation (patch_lanes.hpp, test_responses.cpp) for each SIMD
// level (mdbrief/simd_level.hpp): the portable one in test_responses.cpp, AVX2 and AVX-512 in
// x86/, each compiled with its own target flags. Only plain data crosses the boundary and the
// shared template has internal linkage, so no AVX-compiled copy replaces a baseline one.
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
  size_t (*popcountAnd)(const uint64_t* x, const uint64_t* y, size_t n);
};

// The kernels of the active SIMD level; callers resolve them once per call (or object).
ResponseKernels activeResponseKernels();

ResponseKernels portableResponseKernels();
ResponseKernels avx2ResponseKernels();
ResponseKernels avx512ResponseKernels();

namespace {

// The kernels around one 64-lane comparison; each translation unit instantiates it with its
// own LessMask (bit k = a[k] < b[k]).
template <uint64_t (*LessMask)(const uint8_t*, const uint8_t*)>
ResponseKernels responseKernelsWith() {
  ResponseKernels k;
  k.lessMasks = [](const uint8_t* a, const uint8_t* b, size_t words, uint64_t* column) {
    for (size_t w = 0; w < words; ++w) column[w] = LessMask(a + w * kLanes, b + w * kLanes);
  };
  k.ones = [](const uint8_t* a, const uint8_t* b, size_t words) {
    uint32_t n = 0;
    for (size_t w = 0; w < words; ++w)
      n += static_cast<uint32_t>(__builtin_popcountll(LessMask(a + w * kLanes, b + w * kLanes)));
    return n;
  };
  k.flips = [](const uint8_t* a1, const uint8_t* a2, const uint8_t* b1, const uint8_t* b2, size_t words) {
    uint32_t n = 0;
    for (size_t w = 0; w < words; ++w) {
      const size_t o = w * kLanes;
      n += static_cast<uint32_t>(__builtin_popcountll(LessMask(a1 + o, a2 + o) ^ LessMask(b1 + o, b2 + o)));
    }
    return n;
  };
  k.popcount = [](const uint64_t* x, size_t n) {
    size_t ones = 0;
    for (size_t i = 0; i < n; ++i) ones += static_cast<size_t>(__builtin_popcountll(x[i]));
    return ones;
  };
  k.popcountXor = [](const uint64_t* x, const uint64_t* y, size_t n) {
    size_t ones = 0;
    for (size_t i = 0; i < n; ++i) ones += static_cast<size_t>(__builtin_popcountll(x[i] ^ y[i]));
    return ones;
  };
  k.popcountAnd = [](const uint64_t* x, const uint64_t* y, size_t n) {
    size_t ones = 0;
    for (size_t i = 0; i < n; ++i) ones += static_cast<size_t>(__builtin_popcountll(x[i] & y[i]));
    return ones;
  };
  return k;
}

}  // namespace
}  // namespace mdbrief::train::kernels
