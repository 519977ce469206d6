#pragma once
// Kernels of the test-response evaluation (test_responses.cpp) for each SIMD level
// (mdbrief/simd_level.hpp): the portable one here and in test_responses.cpp, AVX2 and AVX-512
// in x86/, each compiled with its own target flags. Only plain data crosses the boundary and
// the shared template has internal linkage, so no AVX-compiled copy replaces a baseline one.
#include <cstddef>
#include <cstdint>

namespace mdbrief::train::kernels {

// 64 patches (one result word) are transposed into a 1024 x 64 byte block: a test on 64 patches
// is then one comparison of two contiguous 64-byte rows.
constexpr size_t kLanes = 64;

struct ResponseKernels {
  // column[w] = bit k set where block w's row a, lane k < row b, lane k (unsigned), w in
  // [w0, w1); blocks are `blockBytes` apart.
  void (*lessMasks)(const uint8_t* blocks, size_t blockBytes, size_t a, size_t b, size_t w0, size_t w1,
                    uint64_t* column);
  // Number of lanes in blocks [w0, w1) where test (p1, p2) differs between blocks A and B.
  uint32_t (*flips)(const uint8_t* A, const uint8_t* B, size_t blockBytes, size_t p1, size_t p2, size_t w0,
                    size_t w1);
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
  k.lessMasks = [](const uint8_t* blocks, size_t blockBytes, size_t a, size_t b, size_t w0, size_t w1,
                   uint64_t* column) {
    for (size_t w = w0; w < w1; ++w) {
      const uint8_t* block = blocks + w * blockBytes;
      column[w] = LessMask(block + a * kLanes, block + b * kLanes);
    }
  };
  k.flips = [](const uint8_t* A, const uint8_t* B, size_t blockBytes, size_t p1, size_t p2, size_t w0,
               size_t w1) {
    uint32_t n = 0;
    for (size_t w = w0; w < w1; ++w) {
      const uint8_t* ba = A + w * blockBytes;
      const uint8_t* bb = B + w * blockBytes;
      n += static_cast<uint32_t>(__builtin_popcountll(LessMask(ba + p1 * kLanes, ba + p2 * kLanes) ^
                                                      LessMask(bb + p1 * kLanes, bb + p2 * kLanes)));
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
