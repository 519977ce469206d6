// The comparison-response kernels (comparison_response_kernels.hpp) for every SIMD level:
// compiled once per Highway target (hwy/foreach_target.h), the active level's copy chosen at run time
// (mdbrief/internal/base/simd_dispatch.hpp). Comparisons and bit counts are exact at every level.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "trainer/comparison_response_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "mdbrief/internal/base/bit_count-inl.h"

#include "mdbrief/internal/base/simd_dispatch.hpp"
#include "trainer/comparison_response_kernels.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::train::kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using mdbrief::HWY_NAMESPACE::Ones;  // mdbrief/internal/base/bit_count-inl.h

// Bit k = a[k] < b[k] (unsigned), k = 0..63, gathered from the mask bits of each vector.
HWY_INLINE uint64_t LessMask(const uint8_t* a, const uint8_t* b) {
  const hn::ScalableTag<uint8_t> d;
  const size_t lanes = hn::Lanes(d);
  uint64_t m = 0;
  for (size_t k = 0; k < kLanes; k += lanes) {
    uint8_t bits[8] = {};
    hn::StoreMaskBits(d, hn::Lt(hn::LoadU(d, a + k), hn::LoadU(d, b + k)), bits);
    for (size_t byte = 0; 8 * byte < lanes; ++byte) m |= uint64_t{bits[byte]} << (k + 8 * byte);
  }
  return m;
}

void LessMasks(const uint8_t* a, const uint8_t* b, size_t words, uint64_t* column) {
  for (size_t w = 0; w < words; ++w) column[w] = LessMask(a + w * kLanes, b + w * kLanes);
}

uint32_t LessOnes(const uint8_t* a, const uint8_t* b, size_t words) {
  uint32_t n = 0;
  for (size_t w = 0; w < words; ++w) n += Ones(LessMask(a + w * kLanes, b + w * kLanes));
  return n;
}

uint32_t Flips(const uint8_t* a1, const uint8_t* a2, const uint8_t* b1, const uint8_t* b2, size_t words) {
  uint32_t n = 0;
  for (size_t w = 0; w < words; ++w) {
    const size_t o = w * kLanes;
    n += Ones(LessMask(a1 + o, a2 + o) ^ LessMask(b1 + o, b2 + o));
  }
  return n;
}

size_t Popcount(const uint64_t* x, size_t n) {
  size_t ones = 0;
  for (size_t i = 0; i < n; ++i) ones += Ones(x[i]);
  return ones;
}

size_t PopcountXor(const uint64_t* x, const uint64_t* y, size_t n) {
  size_t ones = 0;
  for (size_t i = 0; i < n; ++i) ones += Ones(x[i] ^ y[i]);
  return ones;
}

size_t PopcountAnd(const uint64_t* x, const uint64_t* y, size_t n) {
  size_t ones = 0;
  for (size_t i = 0; i < n; ++i) ones += Ones(x[i] & y[i]);
  return ones;
}

ResponseKernels Kernels() { return {LessMasks, LessOnes, Flips, Popcount, PopcountXor, PopcountAnd, HWY_TARGET}; }

}  // namespace mdbrief::train::kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::train::kernels {

ResponseKernels activeResponseKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::train::kernels
#endif
